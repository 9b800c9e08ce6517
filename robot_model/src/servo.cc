// Joint servos (see servo.h).
#include "robot_model/servo.h"

#include <algorithm>
#include <cmath>

namespace ohrp::model {

Servo::Servo(const RobotMap& robot)
    : robot_(robot),
      ref_(robot.joints.size()),
      rejected_(robot.joints.size(), 0),
      clamped_(robot.joints.size(), 0) {}

void Servo::HoldCurrent(const mjData* d) {
  for (size_t i = 0; i < robot_.joints.size(); ++i) {
    const JointMap& j = robot_.joints[i];
    ref_[i] = shm::JointCommand{};
    ref_[i].mode = shm::JointMode::kPosition;
    ref_[i].q_ref = d->qpos[j.qpos_adr];
    ref_[i].kp = j.default_kp;
    ref_[i].kd = j.default_kd;
  }
}

// the command checks, mode by mode: each mode checks what it uses
bool CommandAcceptable(const shm::JointCommand& c, double q_min, double q_max,
                       double tau_max) noexcept {
  if (!(std::isfinite(c.q_ref) && std::isfinite(c.dq_ref) && std::isfinite(c.tau_ff) &&
        std::isfinite(c.kp) && std::isfinite(c.kd)))
    return false;
  switch (c.mode) {
    case shm::JointMode::kOff:
      return true;
    case shm::JointMode::kPosition:
      if (c.q_ref < q_min - kRangeTolerance || c.q_ref > q_max + kRangeTolerance) return false;
      [[fallthrough]];
    case shm::JointMode::kVelocity:
      if (std::fabs(c.dq_ref) > kMaxJointSpeed) return false;
      if (c.kp < 0 || c.kd < 0 || c.kp > kMaxGain || c.kd > kMaxGain) return false;
      [[fallthrough]];
    case shm::JointMode::kTorque:
      return std::fabs(c.tau_ff) <= tau_max;
  }
  return false;  // unknown mode
}

bool Servo::Valid(int i, const shm::JointCommand& c) const {
  const JointMap& j = robot_.joints[i];
  return CommandAcceptable(c, j.q_min, j.q_max, j.tau_max);
}

int Servo::Accept(const shm::CommandBlock& commands) {
  int rejected = 0;
  const int n = static_cast<int>(ref_.size());
  if (commands.njoint != n) {
    // a block for another robot: every joint holds
    for (int i = 0; i < n; ++i) ++rejected_[i];
    rejected_total_ += n;
    return n;
  }
  for (int i = 0; i < n; ++i) {
    if (Valid(i, commands.joint[i])) {
      ref_[i] = commands.joint[i];
    } else {
      ++rejected_[i];
      ++rejected;
    }
  }
  rejected_total_ += rejected;
  return rejected;
}

void Servo::Apply(const mjModel*, mjData* d) {
  for (size_t i = 0; i < ref_.size(); ++i) {
    const JointMap& j = robot_.joints[i];
    const shm::JointCommand& c = ref_[i];
    const double q = d->qpos[j.qpos_adr];
    const double dq = d->qvel[j.dof_adr];
    double tau = 0;
    switch (c.mode) {
      case shm::JointMode::kOff: tau = 0; break;
      case shm::JointMode::kPosition: tau = c.kp * (c.q_ref - q) + c.kd * (c.dq_ref - dq) + c.tau_ff; break;
      case shm::JointMode::kVelocity: tau = c.kd * (c.dq_ref - dq) + c.tau_ff; break;
      case shm::JointMode::kTorque: tau = c.tau_ff; break;
    }
    // the torque within the joint's limit, then the actuator's control for it
    tau = std::clamp(tau, -j.tau_max, j.tau_max);
    bool clamped = false;
    d->ctrl[j.actuator_id] = j.law.ControlFor(tau, q, dq, &clamped);
    if (clamped) {
      ++clamped_[i];
      ++clamped_total_;
    }
  }
}

}  // namespace ohrp::model
