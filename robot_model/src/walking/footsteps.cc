// Footstep geometry and the per-step limits (see walking/footsteps.h).
#include "walking/footsteps.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "step_geometry.h"

namespace ohrp::walking {
namespace {

constexpr double kTol = 1e-9;  // [m or rad] allowed beyond a limit (rounding of planned steps)
constexpr double kShiftStep = 0.002;  // [m] FitStep's scan of the outward shift that clears the soles

// a number for a message, with 3 decimals
std::string Fmt(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.3f", v);
  return b;
}

// an angle for a message: degrees and radians
std::string Deg(double rad) {
  char b[48];
  std::snprintf(b, sizeof(b), "%.1f deg (%.3f rad)", rad * 180 / M_PI, rad);
  return b;
}

// the four corners of a sole seen from above, counter-clockwise
void Corners(const Eigen::Vector3d& p, double yaw, const Eigen::Vector2d& half,
             Eigen::Vector2d out[4]) {
  const Eigen::Rotation2Dd r(yaw);
  const Eigen::Vector2d c = p.head<2>();
  out[0] = c + r * Eigen::Vector2d(half.x(), half.y());
  out[1] = c + r * Eigen::Vector2d(-half.x(), half.y());
  out[2] = c + r * Eigen::Vector2d(-half.x(), -half.y());
  out[3] = c + r * Eigen::Vector2d(half.x(), -half.y());
}

// distance from point q to segment ab
double PointSegment(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - q).norm();
}

}  // namespace

const char* SideName(int foot) { return foot == kRight ? "right" : "left"; }

double WrapAngle(double a) {
  a = std::remainder(a, 2 * M_PI);
  return a;
}

Frame2 MidFrame(const FeetPose& feet) {
  Frame2 m;
  m.p = 0.5 * (feet.p[kLeft] + feet.p[kRight]);
  m.yaw = feet.yaw[kRight] + 0.5 * WrapAngle(feet.yaw[kLeft] - feet.yaw[kRight]);
  return m;
}

FeetPose After(const FeetPose& feet, const Footstep& step) {
  FeetPose f = feet;
  f.p[step.foot] = step.p;
  f.yaw[step.foot] = step.yaw;
  f.roll[step.foot] = step.roll;
  f.pitch[step.foot] = step.pitch;
  return f;
}

Eigen::Vector2d InFrame(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, double yaw) {
  return Eigen::Rotation2Dd(-yaw) * (p - origin).head<2>();
}

std::string CheckLimits(const StepLimits& l) {
  struct Named {
    const char* name;
    double v;
  };
  for (const Named& n : {Named{"max_forward", l.max_forward},
                         {"max_backward", l.max_backward},
                         {"width", l.width},
                         {"max_side", l.max_side},
                         {"min_width", l.min_width},
                         {"max_turn", l.max_turn},
                         {"max_turn_in", l.max_turn_in},
                         {"sole_half_size x", l.sole_half_size.x()},
                         {"sole_half_size y", l.sole_half_size.y()},
                         {"clearance", l.clearance}})
    if (!std::isfinite(n.v) || n.v < 0)
      return std::string("step limit ") + n.name + " must be a finite number >= 0, not " + Fmt(n.v);
  if (!(l.max_stride_change > 0))  // infinite: no limit
    return "step limit max_stride_change must be > 0 (infinite: none), not " + Fmt(l.max_stride_change);
  if (l.sole_half_size.x() <= 0 || l.sole_half_size.y() <= 0)
    return "step limit sole_half_size must be positive";
  if (l.min_width > l.width)
    return "step limit min_width (" + Fmt(l.min_width) + " m) must not exceed width (" +
           Fmt(l.width) + " m)";
  if (l.width < 2 * l.sole_half_size.y() + l.clearance - kTol)
    return "step limit width (" + Fmt(l.width) +
           " m) leaves the soles side by side closer than "
           "the clearance: at least 2 * sole_half_size y + clearance = " +
           Fmt(2 * l.sole_half_size.y() + l.clearance) + " m";
  return "";
}

double SoleGap(const Eigen::Vector3d& p, double yaw, const Eigen::Vector3d& q, double yaw_q,
               const StepLimits& limits) {
  Eigen::Vector2d a[4], b[4];
  Corners(p, yaw, limits.sole_half_size, a);
  Corners(q, yaw_q, limits.sole_half_size, b);
  // separating axes: the edge normals of both rectangles
  double least_overlap = INFINITY;
  bool separated = false;
  for (const Eigen::Vector2d* poly : {a, b})
    for (int e = 0; e < 2; ++e) {
      const Eigen::Vector2d edge = poly[e + 1] - poly[e];
      const Eigen::Vector2d axis = Eigen::Vector2d(-edge.y(), edge.x()).normalized();
      double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
      for (int i = 0; i < 4; ++i) {
        amin = std::min(amin, a[i].dot(axis));
        amax = std::max(amax, a[i].dot(axis));
        bmin = std::min(bmin, b[i].dot(axis));
        bmax = std::max(bmax, b[i].dot(axis));
      }
      const double overlap = std::min(amax, bmax) - std::max(amin, bmin);
      if (overlap <= 0) separated = true;
      least_overlap = std::min(least_overlap, overlap);
    }
  if (!separated) return -least_overlap;
  // apart: the least corner-to-edge distance either way
  double d = INFINITY;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      d = std::min(d, PointSegment(a[i], b[j], b[(j + 1) % 4]));
      d = std::min(d, PointSegment(b[i], a[j], a[(j + 1) % 4]));
    }
  return d;
}

std::string CheckStep(const FeetPose& feet, const Footstep& step, const StepLimits& limits) {
  Limit which;
  return CheckStepLimit(feet, step, limits, &which);
}

std::string CheckStepLimit(const FeetPose& feet, const Footstep& step, const StepLimits& l,
                           Limit* which) {
  auto refuse = [which](Limit w, const std::string& why) {
    *which = w;
    return why;
  };
  // the step's own numbers
  if (step.foot != kLeft && step.foot != kRight)
    return refuse(Limit::kNumbers,
                  "foot must be left (0) or right (1), not " + std::to_string(step.foot));
  if (!step.p.allFinite() || !std::isfinite(step.yaw))
    return refuse(Limit::kNumbers, "the step's position and yaw must be finite numbers");
  const int s = 1 - step.foot;
  const std::string me = std::string("the ") + SideName(step.foot) + " foot";
  const std::string other = std::string("the ") + SideName(s) + " foot";
  // the landing pose in the stance foot's frame; lateral counted outward
  const Eigen::Vector2d d = InFrame(step.p, feet.p[s], feet.yaw[s]);
  const double out = step.foot == kLeft ? 1 : -1;
  const double lateral = out * d.y();
  const double turn = out * WrapAngle(step.yaw - feet.yaw[s]);
  const double max_lat = l.width + l.max_side;
  const std::string lat_range =
      " (allowed " + Fmt(l.min_width) + " .. " + Fmt(max_lat) + " m beside it, in its frame)";
  // sideways: crossing, too close, too far
  if (lateral < -kTol)
    return refuse(Limit::kCross, me + " would land " + Fmt(-lateral) + " m to the " + SideName(s) +
                                     " of " + other + ": the feet would cross" + lat_range);
  if (lateral < l.min_width - kTol)
    return refuse(Limit::kMinWidth, me + " would land " + Fmt(lateral) + " m beside " + other +
                                        ": min_width is " + Fmt(l.min_width) + " m" + lat_range);
  if (lateral > max_lat + kTol)
    return refuse(Limit::kMaxSide, me + " would land " + Fmt(lateral) + " m beside " + other +
                                       ": width + max_side is " + Fmt(max_lat) + " m" + lat_range);
  // forward and backward
  const std::string fwd_range = " (allowed " + Fmt(-l.max_backward) + " .. " + Fmt(l.max_forward) +
                                " m ahead of it, in its frame)";
  if (d.x() > l.max_forward + kTol)
    return refuse(Limit::kForward, me + " would land " + Fmt(d.x()) + " m ahead of " + other +
                                       ": max_forward is " + Fmt(l.max_forward) + " m" + fwd_range);
  if (-d.x() > l.max_backward + kTol)
    return refuse(Limit::kBackward, me + " would land " + Fmt(-d.x()) + " m behind " + other +
                                        ": max_backward is " + Fmt(l.max_backward) + " m" +
                                        fwd_range);
  // turn out and toes in
  const std::string turn_range =
      " (allowed " + Deg(l.max_turn_in) + " in .. " + Deg(l.max_turn) + " out)";
  if (turn > l.max_turn + kTol)
    return refuse(Limit::kTurn, me + " would turn " + Deg(turn) + " out against " + other +
                                    ": max_turn is " + Deg(l.max_turn) + turn_range);
  if (-turn > l.max_turn_in + kTol)
    return refuse(Limit::kTurnIn, me + " would turn " + Deg(-turn) + " in (toes in) against " +
                                      other + ": max_turn_in is " + Deg(l.max_turn_in) +
                                      turn_range);
  // the physics of the step: its height change against the stance sole, its apex, its time
  const std::string basis = l.physics_basis.empty() ? "" : " (" + l.physics_basis + ")";
  const double rise = step.p.z() - feet.p[s].z();
  if (std::abs(rise) > l.max_rise + kTol)
    return refuse(Limit::kRise, me + " would land " + Fmt(std::abs(rise)) + " m " +
                                    (rise > 0 ? "above " : "below ") + other +
                                    ": out of the range -" + Fmt(l.max_rise) + " .. " +
                                    Fmt(l.max_rise) + " m per step" + basis);
  if (step.height >= 0 && step.height > l.max_apex + kTol)
    return refuse(Limit::kApex, me + " would swing " + Fmt(step.height) +
                                    " m high: out of the range 0 .. " + Fmt(l.max_apex) +
                                    " m" + basis);
  if (step.duration >= 0 &&
      (step.duration < l.min_duration - kTol || step.duration > l.max_duration + kTol))
    return refuse(Limit::kDuration, me + " would step in " + Fmt(step.duration) +
                                        " s: out of the range " + Fmt(l.min_duration) + " .. " +
                                        Fmt(l.max_duration) + " s" + basis);
  // the soles apart by the clearance
  const double gap = SoleGap(step.p, step.yaw, feet.p[s], feet.yaw[s], l);
  if (gap < l.clearance - kTol)
    return refuse(Limit::kClearance,
                  me +
                      (gap < 0 ? " would overlap " + other + " by " + Fmt(-gap) + " m"
                               : " would land " + Fmt(gap) + " m from " + other) +
                      ": clearance is " + Fmt(l.clearance) +
                      " m between the soles (set it further out or "
                      "turn it less)");
  *which = Limit::kNone;
  return "";
}

double FitStep(const FeetPose& feet, Footstep* step, const StepLimits& l) {
  if ((step->foot != kLeft && step->foot != kRight) || !step->p.allFinite() ||
      !std::isfinite(step->yaw))
    return 0;
  const int s = 1 - step->foot;
  const double out = step->foot == kLeft ? 1 : -1;  // outward, in the stance foot's frame
  const Eigen::Rotation2Dd R(feet.yaw[s]);
  const Eigen::Vector2d from = step->p.head<2>();
  // turn, then the place in the stance foot's frame, clamped to the limits
  const double turn0 = out * WrapAngle(step->yaw - feet.yaw[s]);
  const double turn = std::clamp(turn0, -l.max_turn_in, l.max_turn);
  Eigen::Vector2d d = InFrame(step->p, feet.p[s], feet.yaw[s]);
  const double lateral0 = out * d.y();
  double lateral = std::clamp(lateral0, l.min_width, l.width + l.max_side);
  const double forward0 = d.x();
  d.x() = std::clamp(d.x(), -l.max_backward, l.max_forward);
  // a step within the limits (CheckStep's tolerance) stays as it is
  const bool inside = std::abs(turn - turn0) <= kTol && std::abs(lateral - lateral0) <= kTol &&
                      std::abs(d.x() - forward0) <= kTol &&
                      SoleGap(step->p, step->yaw, feet.p[s], feet.yaw[s], l) >= l.clearance - kTol;
  if (inside) return 0;
  double yaw = WrapAngle(feet.yaw[s] + out * turn);
  auto place = [&](double lat) {
    const Eigen::Vector2d xy = feet.p[s].head<2>() + R * Eigen::Vector2d(d.x(), out * lat);
    return Eigen::Vector3d(xy.x(), xy.y(), step->p.z());
  };
  auto clear = [&](double lat, double y) {
    return SoleGap(place(lat), y, feet.p[s], feet.yaw[s], l) >= l.clearance;
  };
  // set out sideways by the least amount that clears the soles; parallel to the stance sole if
  // no lateral place does (side by side at `width` the soles always clear: CheckLimits)
  const double widest = l.width + l.max_side;
  if (!clear(lateral, yaw)) {
    if (!clear(widest, yaw)) yaw = feet.yaw[s];
    double lo = lateral, hi = lateral;
    while (!clear(hi, yaw) && hi < widest) {
      lo = hi;
      hi = std::min(widest, hi + kShiftStep);
    }
    for (int i = 0; i < 30 && hi - lo > 1e-9; ++i) (clear(0.5 * (lo + hi), yaw) ? hi : lo) = 0.5 * (lo + hi);
    lateral = hi;
  }
  const Eigen::Vector3d p = place(lateral);
  step->p.head<2>() = p.head<2>();
  step->yaw = yaw;
  return (step->p.head<2>() - from).norm();
}

std::string CheckSteps(const FeetPose& start, const std::vector<Footstep>& steps,
                       const StepLimits& limits) {
  FeetPose feet = start;
  for (size_t k = 0; k < steps.size(); ++k) {
    const std::string why = CheckStep(feet, steps[k], limits);
    if (!why.empty())
      return "step " + std::to_string(k + 1) + " (" + SideName(steps[k].foot) + "): " + why;
    feet = After(feet, steps[k]);
  }
  return "";
}

}  // namespace ohrp::walking
