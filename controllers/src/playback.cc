// The playback controller.
#include "controllers/playback.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "controllers/posture.h"
#include "controllers/ramp.h"

namespace ohrp::controllers {

std::unique_ptr<PlaybackController> PlaybackController::Create(const PlaybackOptions& options,
                                                               ConfigStatus* status) {
  if (!(std::isfinite(options.ramp) && options.ramp >= 0.0)) {
    *status = ConfigStatus::Fail(ConfigError::kOption, "--ramp must be a finite time >= 0 s");
    return nullptr;
  }
  if (!(std::isfinite(options.time_scale) && options.time_scale > 0.0)) {
    *status = ConfigStatus::Fail(ConfigError::kOption, "--time-scale must be finite and > 0");
    return nullptr;
  }
  std::unique_ptr<PlaybackController> c(new PlaybackController());
  c->options_ = options;
  *status = LoadTrajectory(options.angles_file, &c->angles_);
  if (!status->ok()) return nullptr;
  if (c->angles_.njoint > shm::kMaxJoints) {
    *status = ConfigStatus::Fail(ConfigError::kColumns,
                                 options.angles_file + ": " + std::to_string(c->angles_.njoint) +
                                     " joint columns, more than the segment can carry (" +
                                     std::to_string(shm::kMaxJoints) + ")");
    return nullptr;
  }
  if (!options.velocities_file.empty()) {
    *status = LoadTrajectory(options.velocities_file, &c->velocities_);
    if (!status->ok()) return nullptr;
    *status = CheckCompanion(c->angles_, c->velocities_);
    if (!status->ok()) return nullptr;
    c->have_velocities_ = true;
  }
  if (!options.gains_file.empty()) {
    *status = LoadGains(options.gains_file, &c->gains_);
    if (!status->ok()) return nullptr;
    if (static_cast<int>(c->gains_.kp.size()) != c->angles_.njoint) {
      *status = ConfigStatus::Fail(
          ConfigError::kMismatch, options.gains_file + " has gains for " +
                                      std::to_string(c->gains_.kp.size()) + " joints but " +
                                      options.angles_file + " has " +
                                      std::to_string(c->angles_.njoint) + " joint columns");
      return nullptr;
    }
    c->have_gains_ = true;
  }
  return c;
}

ConfigStatus PlaybackController::on_configure(const shm::SegmentHeader& header) {
  if (angles_.njoint != header.njoint) {
    std::string names;
    for (const std::string& n : joint_names()) names += " " + n;
    return ConfigStatus::Fail(
        ConfigError::kMismatch,
        angles_.source + " has " + std::to_string(angles_.njoint) +
            " joint columns after the time, but the robot has " + std::to_string(header.njoint) +
            " joints (" + names.substr(names.empty() ? 0 : 1) +
            "): the file must have one column per joint, in joint-id order");
  }
  for (std::size_t i = 0; i < angles_.rows(); ++i) {
    ConfigStatus s = CheckWithinLimits(header, angles_.row(i),
                                       angles_.source + ":" + std::to_string(angles_.line[i]));
    if (!s.ok()) return s;
  }
  std::copy_n(angles_.row(0), angles_.njoint, first_row_.begin());
  return ConfigStatus::Ok();
}

void PlaybackController::on_activate(const shm::SensorBlock& sensors) noexcept {
  for (int j = 0; j < njoint(); ++j) {
    start_[j] = std::isfinite(sensors.q[j]) ? sensors.q[j] : first_row_[j];
  }
  start_time_ = sensors.time;
}

void PlaybackController::on_update(const shm::SensorBlock& sensors,
                                   shm::CommandBlock* commands) noexcept {
  const int n = njoint();
  const double t = sensors.time - start_time_;
  if (t < options_.ramp) {
    SampleRamp(start_.data(), first_row_.data(), n, t, options_.ramp, q_ref_.data(),
               dq_ref_.data());
  } else {
    const double t_traj = angles_.start_time() + (t - options_.ramp) * options_.time_scale;
    SampleTrajectory(angles_, t_traj, q_ref_.data());
    if (have_velocities_) {
      if (t_traj < angles_.end_time()) {
        SampleTrajectory(velocities_, t_traj, dq_ref_.data());
      } else {
        std::fill_n(dq_ref_.begin(), n, 0.0);  // holding the last row
      }
    } else {
      SampleSlope(angles_, t_traj, dq_ref_.data());
    }
    for (int j = 0; j < n; ++j) dq_ref_[j] *= options_.time_scale;
  }
  const shm::SegmentHeader& h = header();
  for (int j = 0; j < n; ++j) {
    shm::JointCommand& c = commands->joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q_ref_[j];
    c.dq_ref = dq_ref_[j];
    c.tau_ff = 0.0;
    c.kp = have_gains_ ? gains_.kp[j] : h.default_kp[j];
    c.kd = have_gains_ ? gains_.kd[j] : h.default_kd[j];
  }
}

}  // namespace ohrp::controllers
