// The driver's verification of the boards (see board_checks.h).
#include "hw_driver/board_checks.h"

#include <algorithm>
#include <cmath>

#include "hw_driver/guard.h"

namespace ohrp::hw {
namespace {

constexpr double kRangeMargin = 0.1;      // of the joint's range, beyond it a reading is implausible
constexpr double kTrackingFloor = 0.05;   // [rad or m] smallest tracking bound

bool Bounded(double lo, double hi) { return std::isfinite(lo) && std::isfinite(hi) && hi > lo; }

int LowestBit(uint32_t mask) {
  for (int b = 0; b < 32; ++b)
    if (mask & (1u << b)) return b;
  return -1;
}

}  // namespace

BoardChecks::BoardChecks(const shm::ProducerConfig& robot, int sustain, int tracking_cycles)
    : njoint_(static_cast<int>(robot.joint_names.size())),
      sustain_(std::max(1, sustain)),
      tracking_cycles_(std::max(1, tracking_cycles)) {
  q_lo_.resize(njoint_);
  q_hi_.resize(njoint_);
  tau_max_.resize(njoint_);
  track_bound_.resize(njoint_);
  servo_count_.assign(njoint_, 0);
  track_count_.assign(njoint_, 0);
  for (int j = 0; j < njoint_; ++j) {
    const double lo = robot.q_min[j], hi = robot.q_max[j];
    const double margin = Bounded(lo, hi) ? kRangeMargin * (hi - lo) : 0;
    q_lo_[j] = Bounded(lo, hi) ? lo - margin : -HUGE_VAL;
    q_hi_[j] = Bounded(lo, hi) ? hi + margin : HUGE_VAL;
    tau_max_[j] = robot.tau_max[j];
    const double kp = robot.default_kp[j];
    track_bound_[j] = kp > 0 && std::isfinite(tau_max_[j]) ? std::max(kTrackingFloor, tau_max_[j] / kp)
                                                          : HUGE_VAL;
  }
}

Finding BoardChecks::Plausible(const IoState& in) const noexcept {
  for (int j = 0; j < njoint_; ++j) {
    const double q = in.q[j], dq = in.dq[j];
    double bad = 0;
    bool implausible = false;
    if (!std::isfinite(q) || q < q_lo_[j] || q > q_hi_[j]) {
      implausible = true;
      bad = q;
    } else if (!std::isfinite(dq) || std::fabs(dq) > kMaxJointSpeed) {
      implausible = true;
      bad = dq;
    } else if (!std::isfinite(in.tau[j])) {
      implausible = true;
      bad = in.tau[j];
    }
    if (implausible) return Finding{CheckKind::kImplausible, BoardOf(in, j), j, bad};
  }
  return Finding{};
}

void BoardChecks::Restart() noexcept {
  std::fill(servo_count_.begin(), servo_count_.end(), 0);
  std::fill(track_count_.begin(), track_count_.end(), 0);
  unacked_count_ = 0;
}

Finding BoardChecks::Obeyed(const IoState& in, const bool* servo_on,
                            const shm::JointCommand* refs, const bool* skip) noexcept {
  const bool boards = in.reports & io_report::kBoards;
  if (boards && in.foreign_boards) {
    return Finding{CheckKind::kForeign, LowestBit(in.foreign_boards), -1,
                   static_cast<double>(in.foreign_boards)};
  }
  if (boards && (in.refused_boards & ~in.reset_boards)) {
    const uint32_t m = in.refused_boards & ~in.reset_boards;
    return Finding{CheckKind::kRefused, LowestBit(m), -1, static_cast<double>(m)};
  }
  if (boards) {
    unacked_count_ = in.unacked_boards ? unacked_count_ + 1 : 0;
    if (unacked_count_ >= sustain_) {
      return Finding{CheckKind::kUnacknowledged, LowestBit(in.unacked_boards), -1,
                     static_cast<double>(in.unacked_boards)};
    }
  }
  for (int j = 0; j < njoint_; ++j) {
    if (skip[j]) {
      servo_count_[j] = 0;
      track_count_[j] = 0;
      continue;
    }
    if (in.reports & io_report::kServoState) {
      servo_count_[j] = in.servo_on[j] != servo_on[j] ? servo_count_[j] + 1 : 0;
      if (servo_count_[j] >= sustain_) {
        return Finding{CheckKind::kServoMismatch, BoardOf(in, j), j, in.servo_on[j] ? 1.0 : 0.0};
      }
    }
    if (in.reports & io_report::kFollowsCommands) {
      const shm::JointCommand& r = refs[j];
      double bound = HUGE_VAL;
      if (servo_on[j] && r.mode == shm::JointMode::kPosition && r.kp > 0 &&
          std::isfinite(tau_max_[j])) {
        bound = std::max(kTrackingFloor, tau_max_[j] / r.kp);
      }
      // the error the servo's stiffness fights: its law kp e + kd (dq_ref - dq) + tau_ff over
      // kp. A joint following a moving reference lags it by about kd |dq| / kp with dq_ref = 0
      // (G1's waist roll at 1.5 rad/s: 0.05 rad at kp 889, kd 31) while its torque stays far
      // from the limit: the law explains that lag, the board obeys
      const double law = r.kp > 0 ? std::fabs(r.q_ref - in.q[j] +
                                              (r.kd * (r.dq_ref - in.dq[j]) + r.tau_ff) / r.kp)
                                  : 0.0;
      const double e = std::isfinite(law) ? law : std::fabs(r.q_ref - in.q[j]);
      track_count_[j] = e > bound ? track_count_[j] + 1 : 0;
      if (track_count_[j] >= tracking_cycles_) {
        return Finding{CheckKind::kTracking, BoardOf(in, j), j, r.q_ref - in.q[j]};
      }
    }
  }
  return Finding{};
}

double TiltBetween(const double* a, const double* b) {
  auto unit = [](const double* q) {
    const double n = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return std::isfinite(n) && std::fabs(n - 1) < 0.1;
  };
  if (!unit(a) || !unit(b)) return NAN;
  // the z axis of a frame with quaternion (w, x, y, z), in the world
  auto z_axis = [](const double* q, double* z) {
    const double w = q[0], x = q[1], y = q[2], zz = q[3];
    z[0] = 2 * (x * zz + w * y);
    z[1] = 2 * (y * zz - w * x);
    z[2] = 1 - 2 * (x * x + y * y);
  };
  double za[3], zb[3];
  z_axis(a, za);
  z_axis(b, zb);
  const double c = za[0] * zb[0] + za[1] * zb[1] + za[2] * zb[2];
  const double na = std::sqrt(za[0] * za[0] + za[1] * za[1] + za[2] * za[2]);
  const double nb = std::sqrt(zb[0] * zb[0] + zb[1] * zb[1] + zb[2] * zb[2]);
  return std::acos(std::clamp(c / (na * nb), -1.0, 1.0));
}

}  // namespace ohrp::hw
