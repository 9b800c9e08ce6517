// Command checks and driver-side references (see guard.h).
#include "hw_driver/guard.h"

#include <algorithm>
#include <cmath>

namespace ohrp::hw {

CommandGuard::CommandGuard(const shm::ProducerConfig& robot)
    : q_min_(robot.q_min),
      q_max_(robot.q_max),
      tau_max_(robot.tau_max),
      kp_(robot.default_kp),
      kd_(robot.default_kd),
      ref_(robot.joint_names.size()),
      rejected_(robot.joint_names.size(), 0) {
  const size_t n = robot.joint_names.size();
  q_min_.resize(n, -HUGE_VAL);
  q_max_.resize(n, HUGE_VAL);
  tau_max_.resize(n, HUGE_VAL);
  kp_.resize(n, 0.0);
  kd_.resize(n, 0.0);
}

void CommandGuard::HoldMeasured(const double* q) noexcept {
  for (size_t i = 0; i < ref_.size(); ++i) {
    ref_[i] = shm::JointCommand{};
    ref_[i].mode = shm::JointMode::kPosition;
    ref_[i].q_ref = std::isfinite(q[i]) ? std::clamp(q[i], q_min_[i], q_max_[i]) : 0.0;
    ref_[i].kp = kp_[i];
    ref_[i].kd = kd_[i];
  }
}

bool CommandGuard::Valid(int i, const shm::JointCommand& c) const noexcept {
  return model::CommandAcceptable(c, q_min_[i], q_max_[i], tau_max_[i]);
}

int CommandGuard::Accept(const shm::CommandBlock& commands) noexcept {
  const int n = njoint();
  if (commands.njoint != n) {
    for (int i = 0; i < n; ++i) ++rejected_[i];
    rejected_total_ += n;
    return n;
  }
  int rejected = 0;
  for (int i = 0; i < n; ++i) {
    const shm::JointCommand& c = commands.joint[i];
    if (!Valid(i, c)) {
      ++rejected_[i];
      ++rejected;
      continue;
    }
    ref_[i] = c;
    const double clamped = std::clamp(c.q_ref, q_min_[i], q_max_[i]);
    if (clamped != c.q_ref) {
      ref_[i].q_ref = clamped;
      ++clamped_total_;
    }
  }
  rejected_total_ += rejected;
  return rejected;
}

bool CommandGuard::Set(int i, const shm::JointCommand& c) noexcept {
  if (!Valid(i, c)) return false;
  ref_[i] = c;
  if (c.mode == shm::JointMode::kPosition) ref_[i].q_ref = std::clamp(c.q_ref, q_min_[i], q_max_[i]);
  return true;
}

void CommandGuard::Damp(const double* q, double kp_scale, double kd_scale) noexcept {
  for (size_t i = 0; i < ref_.size(); ++i) {
    shm::JointCommand& r = ref_[i];
    double hold = r.q_ref;
    if (r.mode != shm::JointMode::kPosition || !std::isfinite(hold)) hold = q[i];
    if (!std::isfinite(hold)) hold = 0.0;
    r.mode = shm::JointMode::kPosition;
    r.q_ref = std::clamp(hold, q_min_[i], q_max_[i]);
    r.dq_ref = 0;
    r.tau_ff = 0;
    r.kp = kp_[i] * kp_scale;
    r.kd = kd_[i] * kd_scale;
  }
}

}  // namespace ohrp::hw
