// A sweep file's `parameters` and values (spec_parameters.cc), read for ReadSweep (spec.cc).
#pragma once

#include <set>
#include <string>
#include <vector>

#include "sweep/sweep.h"

namespace YAML {
class Node;
}

namespace ohrp::sweep {

// the sweep file's messages' "sweep 'FILE': line N: " at node `n`, or at `map`'s `key` (the
// runner's reads with kind "sweep"; spec.cc, spec_parameters.cc, draw.cc)
std::string At(const std::string& path, const YAML::Node& n);
std::string AtKey(const std::string& path, const YAML::Node& map, const std::string& key);

// a scalar as a parameter value: numbers in their shortest exact form
bool ReadValue(const YAML::Node& n, Value* v, std::string* why);

// root's `parameters` into s->parameters; each entry (a parameter or a zip group) one axis of
// the grid (the indices of its parameters), every key once (*keys); false with *error
// ("sweep 'FILE': line N: parameters[i]: ...")
bool ReadParameters(const YAML::Node& root, const std::string& path, SweepSpec* s,
                    std::vector<std::vector<size_t>>* axes, std::set<std::string>* keys,
                    std::string* error);

}  // namespace ohrp::sweep
