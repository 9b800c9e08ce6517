// Footstep plans from commands: a relative goal, a velocity, a stop (see walking/footsteps.h).
//
// Every plan is a walk of the mid frame: step k moves the mid frame by an increment expressed in
// its own frame, and the step's foot lands at its nominal place about the new mid frame (half the
// width to its side, the mid frame's yaw), set out sideways when that would touch the stance sole.
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "step_geometry.h"
#include "walking/footsteps.h"

namespace ohrp::walking {
namespace {

constexpr double kZero = 1e-9;        // [m or rad] a goal or a gap below this is none
constexpr int kMaxSteps = 10000;      // a goal needing more is refused
constexpr double kShiftStep = 0.002;  // [m] scan of the outward shift that clears the soles

// a planar mid frame and a per-step increment in it: x, y [m], yaw [rad]
struct Pose2 {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  double yaw = 0;
};

// `m` moved by `inc` given in m's own frame
Pose2 Compose(const Pose2& m, const Pose2& inc) {
  Pose2 r;
  r.p = m.p + Eigen::Rotation2Dd(m.yaw) * inc.p;
  r.yaw = m.yaw + inc.yaw;
  return r;
}

// the side of `foot` in its frame: +1 left, -1 right
double SideSign(int foot) { return foot == kLeft ? 1 : -1; }

// the sole of `foot` at its nominal place about mid frame `m`, at height z, set out by `shift` [m]
Footstep Nominal(const Pose2& m, int foot, double z, double shift, const StepLimits& l) {
  Footstep s;
  s.foot = foot;
  const Eigen::Vector2d xy = m.p + Eigen::Rotation2Dd(m.yaw) *
                                       Eigen::Vector2d(0, SideSign(foot) * (0.5 * l.width + shift));
  s.p = Eigen::Vector3d(xy.x(), xy.y(), z);
  s.yaw = m.yaw;
  return s;
}

// the nominal sole about `m`, set out by the least shift that keeps the clearance from the stance
// sole (none when it is clear); `*shifted` says whether it was set out
Footstep Place(const FeetPose& feet, const Pose2& m, int foot, double z, const StepLimits& l,
               bool* shifted) {
  const int s = 1 - foot;
  auto clear = [&](double shift) {
    const Footstep f = Nominal(m, foot, z, shift, l);
    return SoleGap(f.p, f.yaw, feet.p[s], feet.yaw[s], l) >= l.clearance + 1e-7;
  };
  *shifted = false;
  if (clear(0)) return Nominal(m, foot, z, 0, l);
  // scan outward, then bisect between the last touching and the first clear shift
  double lo = 0, hi = kShiftStep;
  const double limit = l.max_side + l.width;
  while (!clear(hi)) {
    lo = hi;
    hi += kShiftStep;
    if (hi > limit) return Nominal(m, foot, z, 0, l);  // CheckStep will say why
  }
  for (int i = 0; i < 30; ++i) (clear(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
  *shifted = true;
  return Nominal(m, foot, z, hi, l);
}

// the walk of the mid frame from `start` by `inc` (step k by foot first ^ (k & 1)), then the
// closing step(s) that leave both soles nominal about the last mid frame; "" or why not
std::string Walk(const FeetPose& start, const std::vector<Pose2>& inc, int first,
                 const StepLimits& l, std::vector<Footstep>* steps) {
  const Frame2 mid = MidFrame(start);
  Pose2 m;
  m.p = mid.p.head<2>();
  m.yaw = mid.yaw;
  const double z = mid.p.z();
  FeetPose feet = start;
  steps->clear();
  auto add = [&](const Footstep& s) {
    const std::string why = CheckStep(feet, s, l);
    if (!why.empty())
      return "step " + std::to_string(steps->size() + 1) + " (" + SideName(s.foot) + "): " + why;
    steps->push_back(s);
    feet = After(feet, s);
    return std::string();
  };
  // the walk
  int foot = first;
  bool shifted = false;
  for (size_t k = 0; k < inc.size(); ++k, foot = 1 - foot) {
    m = Compose(m, inc[k]);
    const std::string why = add(Place(feet, m, foot, z, l, &shifted));
    if (!why.empty()) return why;
  }
  // closing: the other foot beside it, and the last one again if it was set out
  const int last = 1 - foot;
  std::string why = add(Nominal(m, foot, z, 0, l));
  if (why.empty() && shifted) why = add(Nominal(m, last, z, 0, l));
  return why;
}

// "" when the start stance keeps the limits (either sole as a step beside the other), else why not
std::string StanceProblem(const FeetPose& start, const StepLimits& l) {
  Footstep left, right;
  left.p = start.p[kLeft];
  left.yaw = start.yaw[kLeft];
  right.foot = kRight;
  right.p = start.p[kRight];
  right.yaw = start.yaw[kRight];
  const std::string why = CheckStep(start, left, l);
  if (why.empty() || CheckStep(start, right, l).empty()) return "";
  return "the start stance breaks the limits: " + why;
}

// the first foot for a motion (y, yaw): the side of the larger of the two in its limit's units
int FirstFoot(double y, double yaw, const StepLimits& l) {
  const double ry = std::abs(y) / std::max(l.max_side, kZero);
  const double rt = std::abs(yaw) / std::max(l.max_turn, kZero);
  if (rt > kZero && rt >= ry) return yaw > 0 ? kLeft : kRight;
  if (ry > kZero) return y > 0 ? kLeft : kRight;
  return kLeft;
}

// how far the inward foot of a side step may go sideways: down to min_width and to the soles'
// clearance [m]
double InwardSide(const StepLimits& l) {
  return std::max(0.0, l.width - std::max(l.min_width, 2 * l.sole_half_size.y() + l.clearance));
}

// the increments of an n-step walk to goal g from foot `first`, or false when the limits cannot
// reach it in n steps: the yaw takes each foot's full turn until the goal's (front-loaded, so the
// last steps turn least), the translation is shared among the steps by each foot's capacity in
// the goal's direction, in the rotating mid frame
bool GoalIncrements(const Pose2& g, int n, int first, const StepLimits& l,
                    std::vector<Pose2>* inc) {
  inc->assign(n, Pose2());
  // yaw
  double left = std::abs(g.yaw);
  const double turn_sign = g.yaw >= 0 ? 1 : -1;
  std::vector<double> heading(n + 1, 0.0);
  for (int k = 0, foot = first; k < n; ++k, foot = 1 - foot) {
    const bool out = SideSign(foot) == turn_sign;
    const double d = std::min(left, out ? l.max_turn : l.max_turn_in);
    (*inc)[k].yaw = turn_sign * d;
    left -= d;
    heading[k + 1] = heading[k] + (*inc)[k].yaw;
  }
  if (left > kZero) return false;
  // translation: increments (u.x cx_k, u.y cy_k) in the mid frame before step k sum to g.p
  const bool fwd = g.p.x() >= 0;
  const double side_sign = g.p.y() >= 0 ? 1 : -1;
  std::vector<Eigen::Vector2d> cap(n);
  Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
  for (int k = 0, foot = first; k < n; ++k, foot = 1 - foot) {
    const bool out = SideSign(foot) == side_sign;
    cap[k] =
        Eigen::Vector2d(fwd ? l.max_forward : l.max_backward, out ? l.max_side : InwardSide(l));
    a += Eigen::Rotation2Dd(heading[k]).toRotationMatrix() * cap[k].asDiagonal();
  }
  // a column of zeros (no capacity in a direction the goal does not need) solves as 0
  Eigen::Vector2d u = Eigen::Vector2d::Zero();
  const bool cx = a.col(0).norm() > kZero, cy = a.col(1).norm() > kZero;
  if (cx && cy) {
    if (std::abs(a.determinant()) < 1e-12) return false;
    u = a.lu().solve(g.p);
  } else if (cx) {
    u.x() = a.col(0).dot(g.p) / a.col(0).squaredNorm();
  } else if (cy) {
    u.y() = a.col(1).dot(g.p) / a.col(1).squaredNorm();
  }
  if ((a * u - g.p).norm() > kZero) return false;
  for (int k = 0; k < n; ++k) (*inc)[k].p = u.cwiseProduct(cap[k]);
  return true;
}

// the fewest-step walk to goal g from foot `first`, trying n from a lower bound up; "" or why not
std::string PlanFrom(const FeetPose& start, const Pose2& g, int first, const StepLimits& l,
                     std::vector<Footstep>* steps) {
  // a lower bound on n (halved, only to skip hopeless counts)
  const double reach = std::hypot(std::max(l.max_forward, l.max_backward), l.width + l.max_side);
  const double turn = std::max(l.max_turn, l.max_turn_in);
  const int lo =
      std::max(1, static_cast<int>(0.5 * std::max(g.p.norm() / std::max(reach, kZero),
                                                  std::abs(g.yaw) / std::max(turn, kZero))));
  if (lo > kMaxSteps) return "the goal needs more than " + std::to_string(kMaxSteps) + " steps";
  std::string why = "the limits cannot reach the goal";
  std::vector<Pose2> inc;
  const int hi = std::min(kMaxSteps, std::max(4 * lo, lo + 200));
  for (int n = lo; n <= hi; ++n) {
    if (!GoalIncrements(g, n, first, l, &inc)) continue;
    why = Walk(start, inc, first, l, steps);
    if (why.empty()) return "";
  }
  steps->clear();
  return why;
}

}  // namespace

std::vector<Footstep> PlanToGoal(const FeetPose& start, double x, double y, double yaw,
                                 const StepLimits& limits, std::string* error) {
  std::vector<Footstep> none;
  auto fail = [&](const std::string& why) {
    if (error) *error = "cannot plan the goal: " + why;
    return none;
  };
  if (error) error->clear();
  const std::string bad = CheckLimits(limits);
  if (!bad.empty()) return fail(bad);
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(yaw))
    return fail("x, y and yaw must be finite numbers");
  const std::string stance = StanceProblem(start, limits);
  if (!stance.empty()) return fail(stance);
  Pose2 g;
  g.p = Eigen::Vector2d(x, y);
  // the short way round, but a half turn keeps the direction asked
  g.yaw = std::abs(yaw) > M_PI ? WrapAngle(yaw) : yaw;
  if (g.p.norm() < kZero && std::abs(g.yaw) < kZero) return none;
  // the direction's first foot; the other only when it needs fewer steps
  const int first = FirstFoot(y, g.yaw, limits);
  std::vector<Footstep> a, b;
  const std::string why_a = PlanFrom(start, g, first, limits, &a);
  const std::string why_b = PlanFrom(start, g, 1 - first, limits, &b);
  if (why_a.empty() && (!why_b.empty() || a.size() <= b.size())) return a;
  if (why_b.empty()) return b;
  return fail(why_a);
}

std::vector<Footstep> PlanVelocity(const FeetPose& start, double vx, double vy, double wz,
                                   double time, double step_time, const StepLimits& l,
                                   std::string* note) {
  std::string said;
  auto say = [&](const std::string& s) { said += (said.empty() ? "" : "; ") + s; };
  auto done = [&](std::vector<Footstep> steps) {
    if (note) *note = said;
    return steps;
  };
  // the command's numbers
  const std::string bad = CheckLimits(l);
  if (!bad.empty()) return say(bad), done({});
  const std::string stance = StanceProblem(start, l);
  if (!stance.empty()) return say(stance), done({});
  if (!std::isfinite(vx) || !std::isfinite(vy) || !std::isfinite(wz) || !std::isfinite(time) ||
      !std::isfinite(step_time) || step_time <= 0 || time < 0)
    return say("vx, vy, wz, time >= 0 and step_time > 0 must be finite numbers"), done({});
  const double count = std::round(time / step_time);
  if (time <= 0) return done({});
  if (count > kMaxSteps)
    return say("the walk needs more than " + std::to_string(kMaxSteps) + " steps"), done({});
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
  // per step: the foot on the motion's side takes the larger share of each pair
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
  // walked; where the soles' clearance and the turn together break a limit, slower
  std::vector<Footstep> steps;
  std::string why = Walk(start, inc, first, l, &steps);
  double scale = 1;
  for (int i = 0; i < 40 && !why.empty(); ++i) {
    scale *= 0.9;
    for (auto& d : inc) d.p *= 0.9, d.yaw *= 0.9;
    const std::string again = Walk(start, inc, first, l, &steps);
    if (again.empty()) {
      std::snprintf(b, sizeof(b), "reduced to %.0f%% of the velocity to keep the limits (",
                    100 * scale);
      say(b + why + ")");
    }
    why = again;
  }
  if (!why.empty()) return say("cannot walk from this stance: " + why), done({});
  for (auto& s : steps) s.duration = t;
  return done(steps);
}

std::vector<Footstep> PlanStop(const FeetPose& feet, int last_foot, const StepLimits& limits) {
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
