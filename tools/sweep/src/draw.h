// A sweep parameter's values drawn from a distribution (draw.cc has the syntax).
#pragma once

#include <string>

#include "sweep/sweep.h"

namespace YAML {
class Node;
}

namespace ohrp::sweep {

// Fills p->values with the draws and p->draw with their description; false with `*error`
// ("sweep 'FILE': line N: WHERE KEY: draw: what is wrong").
bool ReadDraw(const YAML::Node& d, const std::string& path, const std::string& where,
              Parameter* p, std::string* error);

}  // namespace ohrp::sweep
