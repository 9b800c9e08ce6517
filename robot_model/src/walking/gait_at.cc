// The walk's timeline at a time (gait.h, Gait::At): the ZMP reference and the ground height
// blended between the stance points, the swinging foot along its travel (onto, off and over
// steps: IsStepEdge) and up to its apex and down, the heel lifted off a stair, the toe-off onto
// one. The steps' placing in time is gait.cc.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "step_geometry.h"
#include "walking/gait.h"

namespace ohrp::walking {
namespace {

constexpr double kStepEdge = 0.01;              // [m] a height change this large is a step
constexpr double kStepVerticalFraction = 0.3;   // [-] of the single support, up and down

}  // namespace

Eigen::Vector3d Gait::Zmp(double t) const {
  GaitState s;
  At(t, &s);
  return s.zmp;
}

double Gait::HeelLift(bool down, double apex) const {
  if (!down || !(options_.sole_half_length > 0)) return 0;
  // as far as the toe stays above the stair at the apex, with a fifth to spare
  return 0.8 * std::asin(std::clamp(apex / options_.sole_half_length, 0.0, 1.0));
}

void Gait::ToeOff(const Phase& p, double phase, double f_travel, GaitState* s) const {
  const int sw = p.step.foot;
  const double half = options_.sole_half_length;
  if (!(half > 0) || !(p.step.p.z() > p.before.p[sw].z()) || !IsStepEdge(p.before, p.step)) return;
  // full by half the vertical lift, level again at half the travel
  const double lift_share = 0.5 * LandingShare(p);
  const double r =
      std::clamp(std::min(phase / std::max(lift_share, 1e-9), 1 - f_travel), 0.0, 1.0);
  const double a = HeelLift(true, p.height) * r;
  if (!(a > 0)) return;
  // about the toe: the sole's centre up by half sin(a) and towards the toe by half (1 - cos(a))
  const double yaw = s->feet.yaw[sw];
  s->feet.pitch[sw] += a;
  s->feet.p[sw].x() += half * (1 - std::cos(a)) * std::cos(yaw);
  s->feet.p[sw].y() += half * (1 - std::cos(a)) * std::sin(yaw);
  s->feet.p[sw].z() += half * std::sin(a);
}

// a height change between lift-off and landing that the tilt of neither sole's surface explains
// (a slope rises by its tilt over the travel): a stair's edge to clear
bool IsStepEdge(const FeetPose& before, const Footstep& step) {
  const int sw = step.foot;
  const double rise = std::abs(step.p.z() - before.p[sw].z());
  const double run = (step.p.head<2>() - before.p[sw].head<2>()).norm();
  const double tilt = std::max({std::abs(step.pitch), std::abs(step.roll),
                                std::abs(before.pitch[sw]), std::abs(before.roll[sw])});
  return rise > kStepEdge + run * std::tan(tilt);
}

// off a stair: an edge whose drop is deeper than the swing's apex. The swing then stays at the
// top until past the nose and comes down late (with the heel first). A slope's drop is no stair
// to leave however long the travel: it keeps the symmetric profile (held at the top, a sole on a
// slope whose travel drops more than the apex came down over a twentieth of the swing)
static bool IsStepDown(const FeetPose& before, const Footstep& step, double apex) {
  const double drop = before.p[step.foot].z() - step.p.z();
  return drop > std::max(kStepEdge, apex) && IsStepEdge(before, step);
}

double Gait::LandingShare(const Phase& p) const {
  const double vf = options_.vertical_fraction;
  return IsStepEdge(p.before, p.step) ? std::max(vf, kStepVerticalFraction) : vf;
}

double Gait::Travel(const Phase& p, double t) const {
  // onto a step the foot rises (and comes down) vertically for longer: its toe clears the riser
  // before it moves over it. Off a step it stays at the top until past the nose and comes down
  // vertically for longer, but leaves the upper stair with the short vertical share: the
  // trailing foot goes forward at once (held back, its ankle ran out of range under a CoM
  // already over the lower stair). A step down no deeper than the swing's apex (a stone) or
  // one the surface's tilt explains (a slope) keeps the symmetric profile: no stair to leave
  const bool edge = IsStepEdge(p.before, p.step);
  const bool down = IsStepDown(p.before, p.step, p.height);
  const double vf = options_.vertical_fraction;
  const double vf_land = LandingShare(p);
  const double vf_lift = edge && !down ? vf_land : vf;
  const double phase = SwingPhase(p, t);
  double f, df, ddf;
  MinJerk((phase - vf_lift) / std::max(1 - vf_lift - vf_land, 1e-9), &f, &df, &ddf);
  return f;
}

double Gait::SwingPhase(const Phase& p, double t) {
  if (p.retime_t >= 0 && t >= p.retime_t)
    return p.retime_phase +
           (1 - p.retime_phase) * (t - p.retime_t) / std::max(p.t_land - p.retime_t, 1e-9);
  return (t - p.t_lift) / std::max(p.t_land - p.t_lift, 1e-9);
}

namespace {

// the ZMP from a to b over [t0, t1] (linear), the ground height over [t0, t2] (minimum jerk), at t
void Blend(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t, double t0, double t1,
           double t2, GaitState* s) noexcept {
  const double T = std::max(t1 - t0, 1e-9), Tz = std::max(t2 - t0, 1e-9);
  const double r = std::clamp((t - t0) / T, 0.0, 1.0);
  double f, df, ddf;
  MinJerk((t - t0) / Tz, &f, &df, &ddf);
  s->zmp.head<2>() = a.head<2>() + r * (b - a).head<2>();
  s->zmp.z() = a.z() + f * (b.z() - a.z());
  s->dz_ground = df * (b.z() - a.z()) / Tz;
  s->ddz_ground = ddf * (b.z() - a.z()) / (Tz * Tz);
}

}  // namespace

void Gait::At(double t, GaitState* s) const {
  const int k = PhaseAt(t);
  s->dz_ground = s->ddz_ground = 0;
  s->support[0] = s->support[1] = true;
  s->swing = -1;
  s->swing_phase = 0;
  s->step = -1;
  if (k < 0) {
    s->feet = start_;
    s->zmp = MidPoint(start_);
    return;
  }
  const Phase& p = steps_[k];
  if (t >= p.t_land) {
    // after the last step: back to the middle of the final stance, then standing
    s->feet = FeetAfter(k);
    // stop_rock: first on the sole that landed for StopHold (gait.h)
    const double hold = StopHold();
    const Eigen::Vector3d from = hold > 0 ? StancePoint(s->feet, p.step.foot) : p.zmp_to;
    const double t_mid = p.t_land + hold + (hold > 0 ? 0 : options_.end_time);
    Blend(from, MidPoint(s->feet), t, p.t_land + hold, t_mid, p.t_land + hold + options_.end_time, s);
    return;
  }
  s->step = k;
  s->feet = p.before;
  // the ground height moves over the whole step (the CoM rises or falls on the stance leg while
  // the other swings), the ZMP over the double support
  Blend(p.zmp_from, p.zmp_to, t, p.t0, p.t_lift, p.t_land, s);
  if (p.hold && t < p.t_lift) s->zmp.head<2>() = p.zmp_from.head<2>();
  if (t < p.t_lift) return;
  // single support: the swing foot from its lift-off pose to the landing
  const int sw = p.step.foot;
  s->swing = sw;
  s->support[sw] = false;
  const double phase = SwingPhase(p, t);
  s->swing_phase = phase;
  const double f_travel = SwingAlong(p, t, s);
  SwingHeight(p, phase, f_travel, s);
  ToeOff(p, phase, f_travel, s);
}

double Gait::SwingAlong(const Phase& p, double t, GaitState* s) const noexcept {
  const int sw = p.step.foot;
  const Eigen::Vector3d& a = p.before.p[sw];
  const Eigen::Vector3d& b = p.step.p;
  // the travel's profile: Travel (onto, off and over steps)
  const double f = Travel(p, t);
  if (p.travel_from >= 0 && f >= p.travel_from) {
    // moved during the swing: on from where the foot was then
    const double r = (f - p.travel_from) / std::max(1 - p.travel_from, 1e-9);
    s->feet.p[sw].head<2>() = p.moved_from + r * (b.head<2>() - p.moved_from);
  } else {
    s->feet.p[sw].head<2>() = a.head<2>() + f * (b - a).head<2>() + std::sin(M_PI * f) * p.detour;
  }
  s->feet.yaw[sw] = p.before.yaw[sw] + f * WrapAngle(p.step.yaw - p.before.yaw[sw]);
  s->feet.roll[sw] = p.before.roll[sw] + f * (p.step.roll - p.before.roll[sw]);
  s->feet.pitch[sw] = p.before.pitch[sw] + f * (p.step.pitch - p.before.pitch[sw]);
  return f;
}

double Gait::LiftTop(const Phase& p, double top) const noexcept {
  const double a = p.before.p[p.step.foot].z();
  if (!(p.step.lift_z > -1e8) || !IsStepEdge(p.before, p.step)) return top;
  return std::clamp(std::max(a, p.step.lift_z) + p.height, a, top);
}

void Gait::SwingHeight(const Phase& p, double phase, double f_travel, GaitState* s) const noexcept {
  const int sw = p.step.foot;
  const Eigen::Vector3d& a = p.before.p[sw];
  const Eigen::Vector3d& b = p.step.p;
  const bool down = IsStepDown(p.before, p.step, p.height);
  const double vf_land = LandingShare(p);
  double f, df, ddf;
  // the apex above the higher end, or above the highest terrain the sole passes over
  const double top = std::max({a.z(), b.z(), p.step.clear_z}) + p.height;
  // up to the top by mid-swing, down from it after mid-swing (off a step: once over the lower
  // stair)
  const double rise_end = 0.5, fall_start = down ? 1 - vf_land : 0.5;
  // over a stair's edge with lower terrain over the first half of the way than the apex's (a
  // stride over a stair onto the next): up to above that terrain by mid-swing, and on up to the
  // top with the travel's first half (at mid-swing the travel is half done: Travel). Off a
  // stair with lower terrain over the second half (a stride past a stair onto the one below):
  // down to above it with the travel's second half, then the vertical landing from there
  const double lift = LiftTop(p, top), land = down ? LandTop(p, top) : top;
  double g, dg, ddg;
  MinJerk(std::min(2 * f_travel, 1.0), &g, &dg, &ddg);
  double h, dh, ddh;
  MinJerk(std::max(2 * f_travel - 1, 0.0), &h, &dh, &ddh);
  const double over = top - h * (top - land);  // the top, lowered past the first stair
  if (phase < rise_end) {
    MinJerk(phase / rise_end, &f, &df, &ddf);
    s->feet.p[sw].z() = a.z() + f * (lift - a.z()) + g * (top - lift) - (top - over);
    // off a step: the heel first (toes down with the lift, level again over the lower stair)
    s->feet.pitch[sw] += HeelLift(down, p.height) * std::min(f, 1 - f_travel);
  } else if (down && phase < fall_start) {
    s->feet.p[sw].z() = over;
    s->feet.pitch[sw] += HeelLift(down, p.height) * (1 - f_travel);
  } else if (phase < fall_start) {
    s->feet.p[sw].z() = top;
  } else {
    // off a step the travel is done by fall_start: the fall starts from `land`
    const double from = down ? land : top;
    MinJerk((phase - fall_start) / (1 - fall_start), &f, &df, &ddf);
    s->feet.p[sw].z() = from + f * (b.z() - from);
  }
}

double Gait::LandTop(const Phase& p, double top) const noexcept {
  const double b = p.step.p.z();
  if (!(p.step.land_z > -1e8)) return top;
  return std::clamp(std::max(b, p.step.land_z) + p.height, b, top);
}

}  // namespace ohrp::walking
