// The scenario's model parameters (see scenario_params.h).
#include "scenario_params.h"

#include <cmath>
#include <set>
#include <vector>

#include "robot_model/joint_params.h"
#include "runner/commands.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

const std::set<std::string> kContactParams = {"stiffness", "exponent", "damping", "friction",
                                              "tangential_stiffness", "tangential_damping"};
const std::set<std::string> kJointParams = {"armature", "damping", "frictionloss"};

double Bound(const std::string& key) {
  return key == "armature" ? model::kMaxArmature
         : key == "damping" ? model::kMaxDamping
                            : model::kMaxFrictionloss;
}

}  // namespace

// contact_params: known soft-foot parameters, positive numbers
bool ReadContactParams(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const YAML::Node n = root["contact_params"];
  if (!n.IsMap()) {
    *error = AtKey(path, root, "contact_params") + "contact_params: must be a mapping, e.g. {stiffness: 3e6, damping: 30}";
    return false;
  }
  if (!KnownKeysOnly(n, kContactParams, path, "contact_params: ", error)) return false;
  for (const auto& kv : n) {
    const std::string key = kv.first.Scalar();
    double v = 0;
    std::string why;
    if (!ReadNumber(kv.second, &v, &why)) {
    } else if (!(v > 0)) {
      why = "must be > 0, not " + kv.second.Scalar();
    } else if (key == "exponent" && (v < 1 || v > 3)) {
      why = "must be in [1, 3], not " + kv.second.Scalar();
    } else {
      s->contact_params[key] = v;
      continue;
    }
    *error = At(path, kv.first) + "contact_params: " + key + ": " + why;
    return false;
  }
  return true;
}

// joint_params: per joint, known keys, numbers in [0, the bound]
bool ReadJointParams(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const YAML::Node n = root["joint_params"];
  if (!n.IsMap() || n.size() == 0) {
    *error = AtKey(path, root, "joint_params") +
             "joint_params: must be a mapping of joints, e.g. {LARM_ELBOW: {armature: 15, damping: 2, "
             "frictionloss: 1.5}}";
    return false;
  }
  for (const auto& joint : n) {
    const std::string name = joint.first.Scalar();
    const std::string where = "joint_params: " + name + ": ";
    if (!joint.second.IsMap() || joint.second.size() == 0) {
      *error = At(path, joint.first) + where + "must be a mapping of armature, damping and/or frictionloss";
      return false;
    }
    if (!KnownKeysOnly(joint.second, kJointParams, path, where, error)) return false;
    for (const auto& kv : joint.second) {
      const std::string key = kv.first.Scalar();
      double v = 0;
      std::string why;
      if (ReadNumber(kv.second, &v, &why)) {
        if (v >= 0 && v <= Bound(key)) {
          s->joint_params[name][key] = v;
          continue;
        }
        why = "must be in [0, " + std::to_string(static_cast<long long>(Bound(key))) + "], not " +
              kv.second.Scalar();
      }
      *error = At(path, kv.first) + where + key + ": " + why;
      return false;
    }
  }
  return true;
}

bool WriteJointParams(const Scenario& s, const std::string& path, std::string* error) {
  std::vector<model::JointParams> joints;
  for (const auto& [name, values] : s.joint_params) {
    model::JointParams& p = joints.emplace_back();
    p.joint = name;
    for (const auto& [key, v] : values)
      (key == "armature" ? p.armature : key == "damping" ? p.damping : p.frictionloss) = v;
  }
  return model::WriteJointParamsFile(path, joints, {"the scenario's joint_params (" + s.file + ")"}, error);
}

}  // namespace ohrp::runner
