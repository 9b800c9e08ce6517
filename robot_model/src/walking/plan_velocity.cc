// Footstep plans at a velocity and to a stop (see walking/footsteps.h).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "plan_walk.h"
#include "step_geometry.h"

namespace ohrp::walking {

std::vector<Footstep> PlanVelocity(const FeetPose& start, double vx, double vy, double wz,
                                   double time, double step_time, const StepLimits& l,
                                   std::string* note) {
  std::string said;
  auto say = [&](const std::string& s) { said += (said.empty() ? "" : "; ") + s; };
  auto done = [&](std::vector<Footstep> steps) {
    if (note) *note = said;
    return steps;
  };
  auto refuse = [&](const std::string& why) {
    say(why);
    return done({});
  };
  // the command's numbers, the limits and the start
  if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(wz) || !std::isfinite(time) ||
      !std::isfinite(step_time) || step_time <= 0 || time < 0)
    return refuse("vx, vy, wz, time >= 0 and step_time > 0 must be finite numbers");
  const std::string bad = CheckLimits(l);
  if (!bad.empty()) return refuse(bad);
  const std::string stance = StanceProblem(start, l);
  if (!stance.empty()) return refuse(stance);
  const double count = std::round(time / step_time);
  if (time <= 0) return done({});
  if (count > kMaxSteps)
    return refuse("the walk needs more than " + std::to_string(kMaxSteps) + " steps");
  const int n = std::max(1, static_cast<int>(count));
  const double t = step_time;
  char b[160];
  // the velocity reduced to the limits: forward per step, sideways and turn per pair of steps
  const double vx_max = l.max_forward / t, vx_min = -l.max_backward / t;
  const double vy_max = (l.max_side + InwardSide(l)) / (2 * t);
  const double wz_max = (l.max_turn + l.max_turn_in) / (2 * t);
  auto clamp = [&](double* v, double lo, double hi, const char* name, const char* why,
                   const char* unit) {
    if (*v >= lo && *v <= hi) return;
    const double c = std::clamp(*v, lo, hi);
    std::snprintf(b, sizeof(b), "%s %.3f %s is beyond %s at %.3f s steps: walking at %.3f %s", name,
                  *v, unit, why, t, c, unit);
    say(b);
    *v = c;
  };
  clamp(&vx, vx_min, vx_max, "vx", "max_forward and max_backward", "m/s");
  clamp(&vy, -vy_max, vy_max, "vy", "max_side and min_width", "m/s");
  clamp(&wz, -wz_max, wz_max, "wz", "max_turn and max_turn_in", "rad/s");
  // per pair of steps 2 v t; the foot on the motion's side takes the larger share (up to its
  // limit), the other the rest
  const int first = FirstFoot(vy, wz, l);
  std::vector<Pose2> inc(n);
  for (int k = 0, foot = first; k < n; ++k, foot = 1 - foot) {
    const double side = 2 * std::abs(vy) * t, turn = 2 * std::abs(wz) * t;
    const bool side_out = SideSign(foot) * vy > 0, turn_out = SideSign(foot) * wz > 0;
    const double ds = side_out ? std::min(side, l.max_side) : side - std::min(side, l.max_side);
    const double dt = turn_out ? std::min(turn, l.max_turn) : turn - std::min(turn, l.max_turn);
    inc[k].p = Eigen::Vector2d(vx * t, std::copysign(ds, vy));
    inc[k].yaw = std::copysign(dt, wz);
  }
  // from and to standing, the stride changes by at most max_stride_change a step
  if (std::isfinite(l.max_stride_change) && std::abs(vx) * t > l.max_stride_change) {
    int ramped = 0;
    for (int k = 0; k < n; ++k) {
      const double most = l.max_stride_change * std::min(k + 1, n - k);
      if (std::abs(inc[k].p.x()) > most) {
        inc[k].p.x() = std::copysign(most, vx);
        ++ramped;
      }
    }
    std::snprintf(b, sizeof(b), "the stride changes by at most max_stride_change %.3f m a step: "
                  "%d step(s) shorter at the start and end", l.max_stride_change, ramped);
    say(b);
  }
  // walked; where the soles' clearance and the turn together break a limit, slower
  std::vector<Footstep> steps;
  std::string why = Walk(start, inc, first, l, &steps);
  double scale = 1;
  for (int i = 0; i < 40 && !why.empty(); ++i) {
    scale *= 0.9;
    for (auto& d : inc) {
      d.p *= 0.9;
      d.yaw *= 0.9;
    }
    const std::string again = Walk(start, inc, first, l, &steps);
    if (again.empty()) {
      std::snprintf(b, sizeof(b), "reduced to %.0f%% of the velocity to keep the limits (",
                    100 * scale);
      say(b + why + ")");
    }
    why = again;
  }
  if (!why.empty()) return refuse("cannot walk from this stance: " + why);
  for (auto& s : steps) s.duration = t;
  return done(steps);
}

std::vector<Footstep> PlanStop(const FeetPose& feet, int last_foot, const StepLimits& limits) {
  if (last_foot != kLeft && last_foot != kRight) return {};
  const int other = 1 - last_foot;
  Footstep s;
  s.foot = other;
  const Eigen::Vector2d xy =
      feet.p[last_foot].head<2>() +
      Eigen::Rotation2Dd(feet.yaw[last_foot]) * Eigen::Vector2d(0, SideSign(other) * limits.width);
  s.p = Eigen::Vector3d(xy.x(), xy.y(), feet.p[last_foot].z());
  s.yaw = feet.yaw[last_foot];
  if ((s.p - feet.p[other]).norm() < kZero && std::abs(WrapAngle(s.yaw - feet.yaw[other])) < kZero)
    return {};
  return {s};
}

}  // namespace ohrp::walking
