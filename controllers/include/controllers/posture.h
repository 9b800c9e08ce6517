// Posture: move smoothly from wherever the robot is to a pose, then hold it.
//
// On activation it takes the joint positions of the first sensor block, then ramps
// (minimum jerk, ramp.h) to the pose over `ramp` seconds of the producer's `time`, and holds.
// Joints the pose does not name hold where they were at activation (never 0). The pose comes
// from a pose file or from a keyframe of a scene (pose.h: FromKeyframe). Every joint is in
// position mode with the producer's default gains times the scales.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "controllers/controller.h"
#include "controllers/pose.h"

namespace ohrp::controllers {

// controllers/poses/hrp1s_halfsit.yaml of the data folder (cli/data_dir.h: <bin>/../share/ohrp)
std::string DefaultPoseFile();

struct PostureOptions {
  std::string pose_file;   // YAML pose (pose.h); empty: DefaultPoseFile()
  double ramp = 2.0;       // [s] of producer time, >= 0 (0: jump)
  double kp_scale = 1.0;   // factor on the producer's default_kp, >= 0
  double kd_scale = 1.0;   // factor on the producer's default_kd, >= 0
};

class PostureController : public Controller {
 public:
  // Checks the options and loads the pose file; null with `*status` set on failure.
  static std::unique_ptr<PostureController> Create(const PostureOptions& options,
                                                   ConfigStatus* status);
  // Checks the options and takes an already made pose (a scene's keyframe); null with
  // `*status` set when the options are wrong.
  static std::unique_ptr<PostureController> Create(const PostureOptions& options, Pose pose,
                                                   ConfigStatus* status);
  // The same from an already parsed pose (tests).
  PostureController(const PostureOptions& options, Pose pose);

  // the target in joint-id order (valid from kInactive on)
  const std::vector<double>& target() const { return target_; }

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_activate(const shm::SensorBlock& sensors) noexcept override;
  void on_update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept override;

 private:
  PostureOptions options_;
  Pose pose_;
  std::vector<double> target_;                     // (njoint)
  std::vector<bool> named_;                        // (njoint) the pose names the joint
  std::array<double, shm::kMaxJoints> start_{};    // pose at activation
  std::array<double, shm::kMaxJoints> q_ref_{};
  std::array<double, shm::kMaxJoints> dq_ref_{};
  double start_time_ = 0.0;                        // producer time at activation [s]
};

// Checks that every value of `q` (joint-id order) lies within the header's joint limits;
// `what(j)` names the value in the message. `only`, when given, selects the joints to check.
ConfigStatus CheckWithinLimits(const shm::SegmentHeader& header, const double* q,
                               const std::string& what, const std::vector<bool>* only = nullptr);

}  // namespace ohrp::controllers
