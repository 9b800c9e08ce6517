// Pose files (YAML) and their mapping onto a robot's joints.
#include "controllers/pose.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ohrp::controllers {
namespace {

std::string At(const std::string& source, const YAML::Node& node) {
  return source + ":" + std::to_string(node.Mark().line + 1) + ": ";
}

}  // namespace

ConfigStatus ParsePose(const std::string& text, const std::string& source, Pose* out) {
  *out = Pose{};
  out->source = source;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return ConfigStatus::Fail(ConfigError::kSyntax,
                              source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) {
    return ConfigStatus::Fail(ConfigError::kSyntax,
                              source + ": expected a mapping with a 'joints:' section");
  }
  bool have_joints = false;
  for (const auto& item : root) {
    const std::string key = item.first.Scalar();
    if (key == "robot" && item.second.IsScalar()) {
      out->robot = item.second.Scalar();
    } else if (key == "description") {
      // free text, ignored
    } else if (key == "joints") {
      have_joints = true;
      if (!item.second.IsMap()) {
        return ConfigStatus::Fail(ConfigError::kSyntax,
                                  At(source, item.second) +
                                      "'joints' must map joint names to positions [rad]");
      }
      for (const auto& joint : item.second) {
        PoseEntry entry;
        entry.joint = joint.first.Scalar();
        entry.line = joint.first.Mark().line + 1;
        if (!joint.second.IsScalar()) {
          return ConfigStatus::Fail(ConfigError::kSyntax, At(source, joint.first) + "joint '" +
                                                              entry.joint +
                                                              "' needs a number [rad]");
        }
        try {
          entry.value = joint.second.as<double>();
        } catch (const YAML::Exception&) {
          return ConfigStatus::Fail(ConfigError::kSyntax,
                                    At(source, joint.second) + "joint '" + entry.joint +
                                        "': '" + joint.second.Scalar() + "' is not a number");
        }
        if (!std::isfinite(entry.value)) {
          return ConfigStatus::Fail(ConfigError::kNonFinite, At(source, joint.second) +
                                                                 "joint '" + entry.joint +
                                                                 "' is not finite");
        }
        for (const PoseEntry& seen : out->joints) {
          if (seen.joint == entry.joint) {
            return ConfigStatus::Fail(ConfigError::kSyntax,
                                      At(source, joint.first) + "joint '" + entry.joint +
                                          "' appears twice (first on line " +
                                          std::to_string(seen.line) + ")");
          }
        }
        out->joints.push_back(entry);
      }
    } else {
      return ConfigStatus::Fail(ConfigError::kSyntax,
                                At(source, item.first) + "unknown key '" + key +
                                    "' (expected robot, description, joints)");
    }
  }
  if (!have_joints) {
    return ConfigStatus::Fail(ConfigError::kSyntax, source + ": no 'joints:' section");
  }
  return ConfigStatus::Ok();
}

ConfigStatus LoadPoseFile(const std::string& path, Pose* out) {
  std::ifstream in(path);
  if (!in) return ConfigStatus::Fail(ConfigError::kFile, path + ": cannot open the pose file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParsePose(text.str(), path, out);
}

Pose FromKeyframe(const std::string& source,
                  const std::vector<std::pair<std::string, double>>& joints) {
  Pose pose;
  pose.source = source;
  pose.from_scene = true;
  for (const auto& [name, value] : joints) pose.joints.push_back({name, value, 0});
  return pose;
}

ConfigStatus ResolvePose(const Pose& pose, const std::vector<std::string>& robot_joints,
                         std::vector<double>* q, std::vector<bool>* named) {
  q->assign(robot_joints.size(), 0.0);
  if (named) named->assign(robot_joints.size(), false);
  std::vector<std::string> unknown;
  std::size_t found = 0;
  for (const PoseEntry& entry : pose.joints) {
    auto it = std::find(robot_joints.begin(), robot_joints.end(), entry.joint);
    if (it == robot_joints.end()) {
      // a scene's keyframe also holds the joints no actuator drives
      if (!pose.from_scene) unknown.push_back(entry.joint + " (line " + std::to_string(entry.line) + ")");
    } else {
      (*q)[it - robot_joints.begin()] = entry.value;
      if (named) (*named)[it - robot_joints.begin()] = true;
      ++found;
    }
  }
  if (pose.from_scene && found == 0 && !robot_joints.empty()) {
    std::string message = pose.source + ": names none of the robot's " +
                          std::to_string(robot_joints.size()) + " joints (";
    for (std::size_t i = 0; i < robot_joints.size() && i < 4; ++i) message += (i ? " " : "") + robot_joints[i];
    message += robot_joints.size() > 4 ? " ...)" : ")";
    message += ". Is this the scene the producer runs?";
    return ConfigStatus::Fail(ConfigError::kUnknownJoint, message);
  }
  if (!unknown.empty()) {
    std::string message = pose.source + ": the robot has no joint";
    message += unknown.size() > 1 ? "s " : " ";
    for (std::size_t i = 0; i < unknown.size(); ++i) message += (i ? ", " : "") + unknown[i];
    message += ". Its " + std::to_string(robot_joints.size()) + " joints are:";
    for (const std::string& name : robot_joints) message += " " + name;
    message += ". Is this pose for another robot?";
    return ConfigStatus::Fail(ConfigError::kUnknownJoint, message);
  }
  return ConfigStatus::Ok();
}

}  // namespace ohrp::controllers
