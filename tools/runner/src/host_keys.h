// The scenario keys that are sim_host options (internal to the runner library): read and checked
// with the one table of them (cli/host_options.h), and passed on to sim_host from it.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "runner/scenario.h"

namespace ohrp::runner {

// Reads every key of the table that `root` has into `s` (its field, or s->host_options), each
// checked against the table's type and range. False with `*error`: "scenario 'FILE': line N: KEY:
// why" (the range named).
bool ReadHostKeys(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error);

// Appends sim_host's options for the scenario's values of the table's keys, in the table's order:
// each value unless it is unset (empty, 0 of an optional number, false) or the table's left_out.
void AppendHostOptions(const Scenario& s, std::vector<std::string>* argv);

}  // namespace ohrp::runner
