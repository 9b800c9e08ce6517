// The controller lifecycle and the command guard.
#include "controllers/controller.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ohrp::controllers {

const char* LifecycleStateName(LifecycleState s) {
  switch (s) {
    case LifecycleState::kUnconfigured: return "unconfigured";
    case LifecycleState::kInactive: return "inactive";
    case LifecycleState::kActive: return "active";
    case LifecycleState::kClosed: return "closed";
  }
  return "?";
}

std::vector<std::string> JointNames(const shm::SegmentHeader& header) {
  const int n = std::clamp(header.njoint, 0, shm::kMaxJoints);
  std::vector<std::string> names;
  names.reserve(n);
  for (int j = 0; j < n; ++j) {
    names.emplace_back(header.joint_names[j], strnlen(header.joint_names[j], shm::kNameLen));
  }
  return names;
}

bool HasLimits(const shm::SegmentHeader& header, int j) {
  return std::isfinite(header.q_min[j]) && std::isfinite(header.q_max[j]) &&
         header.q_min[j] < header.q_max[j];
}

//---------------- transitions ----------------

ConfigStatus Controller::configure(const shm::SegmentHeader& header) {
  if (state_ != LifecycleState::kUnconfigured) {
    return ConfigStatus::Fail(ConfigError::kState, std::string("configure() called in state ") +
                                                       LifecycleStateName(state_));
  }
  if (header.njoint < 0 || header.njoint > shm::kMaxJoints) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              "the segment declares " + std::to_string(header.njoint) +
                                  " joints, outside 0.." + std::to_string(shm::kMaxJoints));
  }
  header_ = header;
  joint_names_ = JointNames(header);
  ConfigStatus status = on_configure(header_);
  if (status.ok()) state_ = LifecycleState::kInactive;
  return status;
}

bool Controller::activate(const shm::SensorBlock& sensors) noexcept {
  if (state_ != LifecycleState::kInactive) return false;
  for (int j = 0; j < header_.njoint; ++j) {
    double q = std::isfinite(sensors.q[j]) ? sensors.q[j] : 0.0;
    if (HasLimits(header_, j)) q = std::clamp(q, header_.q_min[j], header_.q_max[j]);
    last_q_ref_[j] = q;
  }
  on_activate(sensors);
  state_ = LifecycleState::kActive;
  return true;
}

bool Controller::update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept {
  if (state_ != LifecycleState::kActive || commands == nullptr) return false;
  if (sensors.status & shm::status::kDiverged) ++counters_.diverged_sensors;
  commands->njoint = header_.njoint;
  on_update(sensors, commands);
  Guard(sensors, commands);
  ++counters_.updates;
  return true;
}

bool Controller::deactivate() noexcept {
  if (state_ != LifecycleState::kActive) return false;
  on_deactivate();
  state_ = LifecycleState::kInactive;
  return true;
}

bool Controller::close() {
  if (state_ == LifecycleState::kActive || state_ == LifecycleState::kClosed) return false;
  if (state_ == LifecycleState::kInactive) on_close();
  state_ = LifecycleState::kClosed;
  return true;
}

//---------------- command guard ----------------

// Whatever the controller computed, what leaves here is finite and within the joint limits:
// a joint with any non-finite field holds its last good reference with the default gains.
void Controller::Guard(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept {
  commands->njoint = header_.njoint;
  for (int j = 0; j < header_.njoint; ++j) {
    shm::JointCommand& c = commands->joint[j];
    const bool finite = std::isfinite(c.q_ref) && std::isfinite(c.dq_ref) &&
                        std::isfinite(c.tau_ff) && std::isfinite(c.kp) && std::isfinite(c.kd);
    if (!finite) {
      ++counters_.non_finite_fixed;
      c.mode = shm::JointMode::kPosition;
      c.q_ref = last_q_ref_[j];
      c.dq_ref = 0.0;
      c.tau_ff = 0.0;
      c.kp = std::isfinite(header_.default_kp[j]) ? header_.default_kp[j] : 0.0;
      c.kd = std::isfinite(header_.default_kd[j]) ? header_.default_kd[j] : 0.0;
    }
    if (HasLimits(header_, j) && (c.q_ref < header_.q_min[j] || c.q_ref > header_.q_max[j])) {
      ++counters_.clamped;
      c.q_ref = std::clamp(c.q_ref, header_.q_min[j], header_.q_max[j]);
    }
    last_q_ref_[j] = c.q_ref;
  }
  (void)sensors;
}

}  // namespace ohrp::controllers
