// The walk's stepping strategy (see walk.h, AdjustStep): where the stance ankle cannot bring the
// capture point back (the measured DCM beyond what the sole's ZMP range takes back), the swing
// foot lands where the DCM will be, and sooner when that place is out of its reach (beyond the
// leg's reach, or across the stance foot: the DCM grows less over a shorter swing, and the other
// leg steps next); the later steps go on from the new foothold.
#include <algorithm>
#include <cmath>
#include <limits>

#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

constexpr double kGravity = 9.81;       // [m/s^2]
constexpr double kLastMove = 0.1;       // [s] before landing the landing is no longer moved
constexpr double kMinMove = 0.002;      // [m] a change of the landing smaller than this is none
constexpr double kMinSwing = 0.3;       // [s] a shortened single support lasts at least this
constexpr double kMinRest = 0.1;        // [s] and its rest (the foot comes down from where it is)
constexpr double kTimeStep = 0.02;      // [s] the landing times tried
constexpr double kMinShorten = 0.01;    // [s] a change of the landing time smaller than this is none

// `target` (a landing within the step limits) pulled back along the line to `current` (the
// landing planned now) until it is within `D` [m] of the foot at `foot` (walking::
// SwingReachDistance over the rest tried): false when not even the current landing is (that
// landing time is out of the question)
bool WithinSwingReach(double D, const Eigen::Vector2d& foot,
                      const Eigen::Vector2d& current, walking::Footstep* target) {
  const Eigen::Vector2d b = current - foot;
  if (b.norm() > D) return false;
  const Eigen::Vector2d a = target->p.head<2>() - current;
  if ((target->p.head<2>() - foot).norm() <= D) return true;
  // |b + lambda a| = D, the root in (0, 1]
  const double aa = a.squaredNorm(), ab = a.dot(b);
  const double lambda = (-ab + std::sqrt(std::max(ab * ab - aa * (b.squaredNorm() - D * D), 0.0))) /
                        std::max(aa, 1e-12);
  target->p.head<2>() = current + std::clamp(lambda, 0.0, 1.0) * a;
  return true;
}

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
    adjust_planned_land_ = gait.step_land(k);
  }
  const double remaining = gait.step_land(k) - w.t;
  if (remaining < kLastMove) return;
  DcmExcess x;
  if (!DcmBeyondAnkle(w, 1 - sw, &x)) return;
  walking::Footstep best;
  double best_rest = remaining;
  ChooseLanding(k, remaining, x, &best, &best_rest);
  MoveLanding(k, remaining, best, best_rest);
}

bool WalkController::DcmBeyondAnkle(const walking::WalkSample& w, int st,
                                    DcmExcess* x) const noexcept {
  // the DCM error now (the stabilizer's last cycle), in the stance sole's frame
  const StabilizerOutput& out = stabilizer_.output();
  const double h = std::max(input_.c.z() - input_.support.ground_z, 0.1);
  const double omega = std::sqrt(kGravity / h);
  const Eigen::Vector2d dcm_ref = input_.c_ref + input_.dc_ref / omega;
  const Eigen::Rotation2Dd R(w.gait.feet.yaw[st]);
  const Eigen::Vector2d e = R.inverse() * (out.dcm - dcm_ref);
  // what the ankle takes back: the ZMP anywhere in the sole (less the stabilizer's margin);
  // beyond it the error grows as exp(omega t) until the landing
  const Eigen::Vector2d reach = (input_.support.half_size[st].array() -
                                 stabilizer_.gains().support_margin).max(0.0);
  Eigen::Vector2d beyond;
  for (int a = 0; a < 2; ++a)
    beyond[a] = std::copysign(std::max(std::abs(e[a]) - reach[a], 0.0), e[a]);
  if (beyond.isZero()) return false;
  x->omega = omega;
  x->d_plan = dcm_ref - w.gait.feet.p[st].head<2>();
  x->beyond = R * beyond;
  return true;
}

void WalkController::ChooseLanding(int k, double remaining, const DcmExcess& x,
                                   walking::Footstep* best, double* best_rest) const noexcept {
  // the landing times tried: as planned, then shorter. The landing for a rest of r: where the
  // measured DCM will be then (diverging from the stance point, less what the ankle takes back)
  // less the plan's DCM offset at its own landing, so that the later steps go on as planned
  // from there: L + (d_plan + e) exp(omega r) - d_plan exp(omega T), d_plan the plan's DCM from
  // the stance point, e the error beyond the ankle, T the planned rest. Each set within the
  // recovery limits (a leg's reach, no crossing) against the stance sole; the one whose
  // shortfall (the DCM's need it does not meet) plus the time it takes off is least
  const walking::Gait& gait = gen_.gait();
  const double t = gen_.sample().t, omega = x.omega;
  const walking::Footstep now_step = gait.step(k);
  const walking::FeetPose feet = gait.FeetAfter(k - 1);
  const double shortest = walk_options_.stepping_timing
                              ? std::max(kMinRest, gait.step_lift(k) + kMinSwing - t)
                              : remaining;
  const Eigen::Vector2d& d_plan = x.d_plan;
  const Eigen::Vector2d& e_beyond = x.beyond;
  const walking::WalkSample& w = gen_.sample();
  const int sw = w.gait.swing;
  const Eigen::Rotation2Dd R(w.gait.feet.yaw[1 - sw]);  // the stance sole's frame
  const Eigen::Vector2d land_reach = (input_.support.half_size[sw].array() -
                                      stabilizer_.gains().support_margin).max(0.0);
  // from the landing as first planned (the plan's DCM is not re-based: its error stays until the
  // new footholds take it back), at its planned time
  const Eigen::Vector2d nominal =
      adjust_planned_.p.head<2>() - d_plan * std::exp(omega * (adjust_planned_land_ - t));
  const Eigen::Vector2d foot = w.gait.feet.p[sw].head<2>();
  *best = now_step;
  *best_rest = remaining;
  double best_cost = std::numeric_limits<double>::infinity();
  for (double rest = remaining; rest >= shortest - 1e-9; rest -= kTimeStep) {
    walking::Footstep target = now_step;
    const Eigen::Vector2d ideal = nominal + (d_plan + e_beyond) * std::exp(omega * rest);
    // the landed sole's ankle takes back as much as the stance one: the landing moves only by
    // what the DCM's offset from the plan at landing needs beyond that (the stance sole's frame)
    Eigen::Vector2d shift = R.inverse() * (ideal - adjust_planned_.p.head<2>());
    if (walk_options_.stepping_deadband)
      for (int a = 0; a < 2; ++a)
        shift[a] = std::copysign(std::max(std::abs(shift[a]) - land_reach[a], 0.0), shift[a]);
    const Eigen::Vector2d want =
        adjust_planned_.p.head<2>() + walk_options_.stepping_gain * (R * shift);
    target.p.head<2>() = want;
    walking::FitStep(feet, &target, recovery_limits_);
    // landing time and place together: the foot travels no farther than the hip can swing it
    // over this rest (a landing out of that reach is brought back towards the current one)
    const double reach_d = walking::SwingReachDistance(
        swing_accel_limit_, w.gait.swing_phase, gait.options().vertical_fraction, rest);
    if (!WithinSwingReach(reach_d, foot, now_step.p.head<2>(), &target)) continue;
    const double cost = (want - target.p.head<2>()).norm() + walk_options_.stepping_time_cost * (remaining - rest);
    if (cost < best_cost) {
      best_cost = cost;
      *best = target;
      *best_rest = rest;
    }
  }
}

void WalkController::MoveLanding(int k, double remaining, const walking::Footstep& best,
                                 double best_rest) noexcept {
  const walking::Gait& gait = gen_.gait();
  const double t = gen_.sample().t;
  const Eigen::Vector2d now = gait.step(k).p.head<2>();
  const bool sooner = remaining - best_rest >= kMinShorten;
  if ((best.p.head<2>() - now).norm() < kMinMove && !sooner) return;
  const double t_land = sooner ? t + best_rest : gait.step_land(k);
  if (!gen_.AdjustStep(k, best.p.head<2>(), t_land, true)) return;
  // the later steps of the command go on from the new foothold (Remap adds this)
  recovery_shift_ += best.p.head<2>() - now;
  if (sooner) {
    walk_stats_.max_shorten = std::max(walk_stats_.max_shorten,
                                       adjust_planned_land_ - t_land);
    if (adjust_planned_land_ - (remaining + t) < kMinShorten) ++walk_stats_.steps_shortened;
  }
  // the plan goes on from the robot's state: its CoM and velocity onto the measured (the
  // stabilizer no longer pulls the robot back onto the plan it was pushed off)
  if (walk_options_.stepping_rebase)
    gen_.ShiftCoM(input_.c.head<2>() - input_.c_ref, input_.dc.head<2>() - input_.dc_ref);
  const double moved = (best.p.head<2>() - adjust_planned_.p.head<2>()).norm();
  if (moved > walk_stats_.max_adjust) walk_stats_.max_adjust = moved;
  if (now == adjust_planned_.p.head<2>() && moved > 0) ++walk_stats_.steps_adjusted;
}

}  // namespace ohrp::controllers
