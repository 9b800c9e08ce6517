// Pose files: joint targets by joint name, in YAML.
//
//   robot: SampleRobot        # optional, informative
//   description: ...          # optional
//   joints:                   # required: joint name -> position [rad or m]
//     RLEG_HIP_P: -0.3491
//     RLEG_KNEE: 0.6981
//
// Joints the file does not name are reported by ResolvePose (`named`), so that posture holds
// them where they are (a caller that does not ask gets 0). A name the robot does not have is an
// error that lists the robot's joints. Values must be finite numbers; a name may appear once.
// A pose may also come from a keyframe of an MJCF scene (FromKeyframe): it names every joint of
// the scene, and the joints the segment does not command (passive ones) are skipped.
#pragma once

#include <string>
#include <utility>
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
  bool from_scene = false;  // a scene's keyframe: joints the robot does not command are skipped
};

// A pose from a scene's keyframe: `joints` (name, position) as read from the scene (e.g. by
// model::KeyframeJointPositions), `source` naming the scene and keyframe for messages.
Pose FromKeyframe(const std::string& source,
                  const std::vector<std::pair<std::string, double>>& joints);

// Parses YAML text; `source` names it in messages.
ConfigStatus ParsePose(const std::string& text, const std::string& source, Pose* out);
// Reads and parses a pose file.
ConfigStatus LoadPoseFile(const std::string& path, Pose* out);

// Maps `pose` onto a robot's joints (joint-id order): q->size() == robot_joints.size(),
// unnamed joints 0, and when `named` is given, (*named)[j] says whether the pose names joint j.
// Fails with kUnknownJoint when the pose names a joint the robot lacks (a pose from a scene:
// when it names none of the robot's joints, i.e. it is another robot's scene).
ConfigStatus ResolvePose(const Pose& pose, const std::vector<std::string>& robot_joints,
                         std::vector<double>* q, std::vector<bool>* named = nullptr);

}  // namespace ohrp::controllers
