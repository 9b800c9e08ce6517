// Reading one entry of a scenario's `checks` list against the table of check types (internal
// to the runner library; see runner/check_keys.h).
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "runner/scenario.h"

namespace ohrp::runner {

// Reads entry `index` of the `checks` list for a run of `duration` simulated seconds. Returns
// false with `*error` naming the file, the line, the check and the key that is wrong. Numbers
// are stored in `out->params` as "%.17g", lists joined with ',', booleans as "true"/"false".
bool ParseCheck(const YAML::Node& entry, size_t index, double duration, const std::string& path,
                CheckSpec* out, std::string* error);

}  // namespace ohrp::runner
