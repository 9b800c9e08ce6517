// Scenario keys by path (internal to the sweep library): "contact_params.stiffness",
// "pushes[0].impulse", "controllers[0].args[1]". SetKey and NumberText are public (sweep.h).
#pragma once

#include <string>
#include <vector>

#include "sweep/sweep.h"

namespace ohrp::sweep {

// one part of a key: a mapping key (name) or a list index (index >= 0)
struct Token {
  std::string name;
  long index = -1;
};

// Splits a key into its parts. False with `*why` (an empty part, a bad index) otherwise.
bool SplitKey(const std::string& key, std::vector<Token>* out, std::string* why);

}  // namespace ohrp::sweep
