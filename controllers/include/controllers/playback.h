// Playback: play a joint trajectory against the producer's clock, like hrpsys's sequence
// player.
//
//   t = producer time - producer time at activation [s]
//   0 <= t < ramp      minimum-jerk ramp from the pose at activation to the first row
//   t >= ramp          the trajectory at t_traj = start_time + (t - ramp) * time_scale,
//                      linearly interpolated; after the last row the last row is held
// Velocity references: from the velocity file when given (interpolated, times time_scale);
// otherwise the slope of the interpolated positions (finite differences of neighbouring rows,
// times time_scale), which is consistent with the position references; 0 while holding.
// During the ramp: the ramp's own derivative.
// Gains: the gain file's P and D when given, else the producer's default_kp / default_kd.
// The trajectory's joint columns must equal the robot's joint count, and every row must lie
// within the robot's joint limits.
#pragma once

#include <array>
#include <memory>
#include <string>

#include "controllers/controller.h"
#include "controllers/trajectory.h"

namespace ohrp::controllers {

struct PlaybackOptions {
  std::string angles_file;      // required
  std::string velocities_file;  // optional
  std::string gains_file;       // optional
  double ramp = 2.0;            // [s] of producer time, >= 0
  double time_scale = 1.0;      // trajectory seconds per producer second, > 0
};

class PlaybackController : public Controller {
 public:
  // Checks the options and loads the files; null with `*status` set on failure.
  static std::unique_ptr<PlaybackController> Create(const PlaybackOptions& options,
                                                    ConfigStatus* status);

  const Trajectory& angles() const { return angles_; }
  // producer time [s] after activation at which the trajectory's last row is reached
  double end_offset() const { return options_.ramp + angles_.duration() / options_.time_scale; }
  // the trajectory is the motion: a hold of the self-collision guard leaves it not done
  bool hold_is_failure() const override { return true; }

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader& header) override;
  void on_activate(const shm::SensorBlock& sensors) noexcept override;
  void on_update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept override;

 private:
  PlaybackController() = default;
  PlaybackOptions options_;
  Trajectory angles_;
  Trajectory velocities_;   // empty when not given
  Gains gains_;             // empty when not given
  bool have_velocities_ = false;
  bool have_gains_ = false;
  std::array<double, shm::kMaxJoints> start_{};
  std::array<double, shm::kMaxJoints> first_row_{};
  std::array<double, shm::kMaxJoints> q_ref_{};
  std::array<double, shm::kMaxJoints> dq_ref_{};
  double start_time_ = 0.0;  // producer time at activation [s]
};

}  // namespace ohrp::controllers
