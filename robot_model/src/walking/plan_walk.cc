// The walk of the mid frame (see plan_walk.h).
#include "plan_walk.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace ohrp::walking {
namespace {

constexpr double kShiftStep = 0.002;  // [m] scan of the outward shift that clears the soles

// `m` moved by `inc` given in m's own frame
Pose2 Compose(const Pose2& m, const Pose2& inc) {
  Pose2 r;
  r.p = m.p + Eigen::Rotation2Dd(m.yaw) * inc.p;
  r.yaw = m.yaw + inc.yaw;
  return r;
}

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

}  // namespace

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

int FirstFoot(double y, double yaw, const StepLimits& l) {
  const double ry = std::abs(y) / std::max(l.max_side, kZero);
  const double rt = std::abs(yaw) / std::max(l.max_turn, kZero);
  if (rt > kZero && rt >= ry) return yaw > 0 ? kLeft : kRight;
  if (ry > kZero) return y > 0 ? kLeft : kRight;
  return kLeft;
}

double InwardSide(const StepLimits& l) {
  return std::max(0.0, l.width - std::max(l.min_width, 2 * l.sole_half_size.y() + l.clearance));
}

}  // namespace ohrp::walking
