// The walk's stepping strategy (see walk.h, AdjustStep): where the stance ankle cannot bring the
// capture point back (the measured DCM beyond what the sole's ZMP range takes back), the swing
// foot lands where the DCM will be.
#include <algorithm>
#include <cmath>

#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

constexpr double kGravity = 9.81;       // [m/s^2]
constexpr double kLastMove = 0.1;       // [s] before landing the landing is no longer moved
constexpr double kMinMove = 0.002;      // [m] a change of the landing smaller than this is none

}  // namespace

void WalkController::AdjustStep() noexcept {
  if (!walk_options_.stepping) return;
  const walking::WalkSample& w = gen_.sample();
  const int k = w.gait.step, sw = w.gait.swing;
  if (k < 0 || sw < 0) return;
  const walking::Gait& gait = gen_.gait();
  if (k != adjust_step_) {  // a new swing: its landing as planned
    adjust_step_ = k;
    adjust_planned_ = gait.step(k);
  }
  const double remaining = gait.step_land(k) - w.t;
  if (remaining < kLastMove) return;
  // the DCM error now (the stabilizer's last cycle), in the stance sole's frame
  const StabilizerOutput& out = stabilizer_.output();
  const double h = std::max(input_.c.z() - input_.support.ground_z, 0.1);
  const double omega = std::sqrt(kGravity / h);
  const Eigen::Vector2d dcm_ref = input_.c_ref + input_.dc_ref / omega;
  const int st = 1 - sw;
  const Eigen::Rotation2Dd R(w.gait.feet.yaw[st]);
  const Eigen::Vector2d e = R.inverse() * (out.dcm - dcm_ref);
  // what the ankle takes back: the ZMP anywhere in the sole (less the stabilizer's margin);
  // beyond it the error grows as exp(omega t) until the landing
  const Eigen::Vector2d reach = (input_.support.half_size[st].array() -
                                 stabilizer_.gains().support_margin).max(0.0);
  Eigen::Vector2d beyond;
  for (int a = 0; a < 2; ++a)
    beyond[a] = std::copysign(std::max(std::abs(e[a]) - reach[a], 0.0), e[a]);
  if (beyond.isZero()) return;
  const Eigen::Vector2d shift = R * (beyond * std::exp(omega * remaining));
  // the landing moved by that, kept within the recovery limits (a leg's reach) against the
  // stance sole
  walking::Footstep target = gait.step(k);
  target.p.head<2>() += shift;
  const walking::FeetPose feet = gait.FeetAfter(k - 1);
  walking::FitStep(feet, &target, recovery_limits_);
  const Eigen::Vector2d now = gait.step(k).p.head<2>();
  if ((target.p.head<2>() - now).norm() < kMinMove) return;
  if (!gen_.AdjustLanding(k, target.p.head<2>())) return;
  // the plan goes on from the robot's state: its CoM and velocity onto the measured (the
  // stabilizer no longer pulls the robot back onto the plan it was pushed off)
  gen_.ShiftCoM(input_.c.head<2>() - input_.c_ref, input_.dc.head<2>() - input_.dc_ref);
  const double moved = (target.p.head<2>() - adjust_planned_.p.head<2>()).norm();
  if (moved > walk_stats_.max_adjust) walk_stats_.max_adjust = moved;
  if (now == adjust_planned_.p.head<2>()) ++walk_stats_.steps_adjusted;
}

}  // namespace ohrp::controllers
