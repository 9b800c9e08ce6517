// Pose files: joint targets by joint name, in YAML.
//
//   robot: SampleRobot        # optional, informative
//   description: ...          # optional
//   joints:                   # required: joint name -> position [rad or m]
//     RLEG_HIP_P: -0.3491
//     RLEG_KNEE: 0.6981
//
// Joints the file does not name get 0. A name the robot does not have is an error that lists
// the robot's joints. Values must be finite numbers; a name may appear once.
#pragma once

#include <string>
#include <vector>

#include "controllers/config_status.h"

namespace ohrp::controllers {

struct PoseEntry {
  std::string joint;
  double value = 0.0;  // [rad or m]
  int line = 0;        // 1-based line in the source, for messages
};

struct Pose {
  std::string source;    // file name, for messages
  std::string robot;     // the optional `robot:` field ("" when absent)
  std::vector<PoseEntry> joints;
};

// Parses YAML text; `source` names it in messages.
ConfigStatus ParsePose(const std::string& text, const std::string& source, Pose* out);
// Reads and parses a pose file.
ConfigStatus LoadPoseFile(const std::string& path, Pose* out);

// Maps `pose` onto a robot's joints (joint-id order): q->size() == robot_joints.size(),
// unnamed joints 0. Fails with kUnknownJoint when the pose names a joint the robot lacks.
ConfigStatus ResolvePose(const Pose& pose, const std::vector<std::string>& robot_joints,
                         std::vector<double>* q);

}  // namespace ohrp::controllers
