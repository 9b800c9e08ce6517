// The scenario's model parameters (internal to the runner library): the soles' soft-contact
// parameters (`contact_params:`, passed as sim_host's --contact-* options) and the joints'
// (`joint_params:`, written to the run folder as the file sim_host's --joint-file applies:
// runner/commands.h), each key and value checked before anything runs.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "runner/scenario.h"

namespace ohrp::runner {

// contact_params: {stiffness: 3e6, damping: 30, ...}: known keys, positive numbers.
bool ReadContactParams(const YAML::Node& root, const std::string& path, Scenario* s,
                       std::string* error);

// joint_params: {JOINT: {armature: X, damping: Y, frictionloss: Z}, ...}: known keys, numbers in
// [0, the bound of robot_model/joint_params.h]; the joints are checked against the model with
// the scenario's other names (model_names.cc).
bool ReadJointParams(const YAML::Node& root, const std::string& path, Scenario* s,
                     std::string* error);

}  // namespace ohrp::runner
