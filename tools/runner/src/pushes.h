// The scenario key `pushes` (internal to the runner library; see runner/scenario.h).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "runner/scenario.h"

namespace ohrp::runner {

// Reads the `pushes` list. Returns false with `*error` naming the file, the line, the push and
// the key that is wrong.
bool ParsePushes(const YAML::Node& list, const std::string& path, std::vector<PushSpec>* out,
                 std::string* error);

}  // namespace ohrp::runner
