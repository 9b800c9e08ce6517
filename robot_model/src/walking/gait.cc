// The walk's timeline (gait.h): the steps placed in time (Start, Replace), the swing's detour
// around the stance sole, the landings moved or delayed during a swing. What the timeline gives
// at a time (the ZMP, the ground height, the feet) is gait_at.cc.
#include "walking/gait.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "step_geometry.h"

namespace ohrp::walking {
namespace {

constexpr int kDetourSamples = 19;               // points of the swing path checked (ends out)
constexpr double kDetourStep = 0.005;           // [m] the detour's increments
constexpr double kMaxDetour = 0.1;              // [m] at most

}  // namespace

void MinJerk(double s, double* f, double* df, double* ddf) {
  if (s <= 0 || s >= 1) {
    *f = s <= 0 ? 0 : 1;
    *df = *ddf = 0;
    return;
  }
  const double s2 = s * s, s3 = s2 * s;
  *f = s3 * (10 - 15 * s + 6 * s2);
  *df = 30 * s2 * (1 - 2 * s + s2);
  *ddf = 60 * s * (1 - 3 * s + 2 * s2);
}

std::string CheckGaitOptions(const GaitOptions& o) {
  const auto finite = [](double v) { return std::isfinite(v); };
  if (!finite(o.step_time) || o.step_time < 0.2 || o.step_time > 10)
    return "step_time must be in [0.2, 10] s (got " + std::to_string(o.step_time) + ")";
  if (!finite(o.double_support_ratio) || o.double_support_ratio < 0.05 || o.double_support_ratio > 0.9)
    return "double_support_ratio must be in [0.05, 0.9] (got " +
           std::to_string(o.double_support_ratio) + ")";
  if (!finite(o.step_height) || o.step_height < 0 || o.step_height > 0.3)
    return "step_height must be in [0, 0.3] m (got " + std::to_string(o.step_height) + ")";
  if (!finite(o.vertical_fraction) || o.vertical_fraction < 0 || o.vertical_fraction > 0.4)
    return "vertical_fraction must be in [0, 0.4] (got " + std::to_string(o.vertical_fraction) + ")";
  if (!finite(o.start_delay) || o.start_delay < 0 || o.start_delay > 10)
    return "start_delay must be in [0, 10] s (got " + std::to_string(o.start_delay) + ")";
  if (!finite(o.start_time) || o.start_time < 0.1 || o.start_time > 10)
    return "start_time must be in [0.1, 10] s (got " + std::to_string(o.start_time) + ")";
  if (!finite(o.end_time) || o.end_time < 0.1 || o.end_time > 10)
    return "end_time must be in [0.1, 10] s (got " + std::to_string(o.end_time) + ")";
  if (!finite(o.zmp_forward) || std::abs(o.zmp_forward) > 0.1)
    return "zmp_forward must be within +-0.1 m (got " + std::to_string(o.zmp_forward) + ")";
  return "";
}

double SwingPeakAcceleration(const GaitOptions& o, double travel) {
  const double T = o.step_time * (1 - o.double_support_ratio) * (1 - 2 * o.vertical_fraction);
  if (!(T > 0)) return std::numeric_limits<double>::infinity();
  return 10 / std::sqrt(3.0) * travel / (T * T);
}

double SwingAccelerationLimit(double tau_max, double tau_gravity, double inertia, double hip_height) {
  if (!(inertia > 0)) return std::numeric_limits<double>::infinity();
  return std::max(tau_max - tau_gravity, 0.0) * hip_height / inertia;
}

double SwingReachDistance(double accel, double phase, double vertical, double rest) {
  if (std::isinf(accel)) return accel;
  phase = std::clamp(phase, 0.0, 1.0);
  vertical = std::clamp(vertical, 0.0, 0.49);
  double f, df, ddf;
  MinJerk(std::clamp((phase - vertical) / (1 - 2 * vertical), 0.0, 1.0), &f, &df, &ddf);
  const double Tu = rest * (1 - 2 * vertical) / std::max(1 - phase, 1e-6);
  return accel * std::max(1 - f, 0.0) * Tu * Tu * std::sqrt(3.0) / 10;
}

double StepDownDrop(const GaitOptions& o, double depth, double reach_xy) {
  if (!(depth > 0) || !(o.leg_reach > 0) || !(o.hip_height > 0)) return 0;
  // the hip midway between the soles at landing: horizontally half the step from the landing sole
  const double d = 0.5 * reach_xy;
  const double vertical = std::sqrt(std::max(o.leg_reach * o.leg_reach - d * d, 0.0));
  return std::clamp(o.hip_height + depth - vertical, 0.0, depth);
}

double StepUpRise(const GaitOptions& o, double height, double reach_xy) {
  if (!(height > 0) || !(o.leg_reach > 0) || !(o.hip_height > 0)) return 0;
  // the trailing leg's sole half the step behind the hip when it leaves the ground
  const double d = 0.5 * reach_xy;
  const double vertical = std::sqrt(std::max(o.leg_reach * o.leg_reach - d * d, 0.0));
  return std::clamp(vertical - o.hip_height, 0.0, height);
}

void Gait::Start(double t, const FeetPose& feet, const GaitOptions& options) {
  options_ = options;
  t_start_ = t;
  start_ = feet;
  steps_.clear();
}

Eigen::Vector3d Gait::StancePoint(const FeetPose& feet, int foot) const {
  const double c = std::cos(feet.yaw[foot]), s = std::sin(feet.yaw[foot]);
  return feet.p[foot] + Eigen::Vector3d(c * options_.zmp_forward, s * options_.zmp_forward, 0);
}

Eigen::Vector3d Gait::MidPoint(const FeetPose& feet) const { return 0.5 * (feet.p[0] + feet.p[1]); }

FeetPose Gait::FeetAfter(int k) const {
  if (k < 0) return start_;
  return After(steps_[k].before, steps_[k].step);
}

const Footstep* Gait::LastStepOf(int foot, int before) const {
  for (int k = std::min(before, static_cast<int>(steps_.size())) - 1; k >= 0; --k)
    if (steps_[k].step.foot == foot) return &steps_[k].step;
  return nullptr;
}

const Footstep* Gait::Standing(int foot, double t) const {
  const int k = PhaseAt(t);
  return LastStepOf(foot, k >= 0 && t >= steps_[k].t_land ? k + 1 : k);
}

int Gait::PhaseAt(double t) const {
  // the last phase with t0 <= t
  const auto it = std::upper_bound(steps_.begin(), steps_.end(), t,
                                   [](double v, const Phase& p) { return v < p.t0; });
  return static_cast<int>(it - steps_.begin()) - 1;
}

double Gait::end_time() const {
  return steps_.empty() ? t_start_ : steps_.back().t_land + StopHold() + options_.end_time;
}

double Gait::StopHold() const {
  if (!options_.stop_rock || steps_.empty()) return 0;
  const double T = steps_.back().step.duration > 0 ? steps_.back().step.duration : options_.step_time;
  return 0.5 * (1 - options_.double_support_ratio) * T;
}

int Gait::Replace(double now, const std::vector<Footstep>& steps) {
  // keep the steps whose double support has begun
  int kept = 0;
  while (kept < static_cast<int>(steps_.size()) && steps_[kept].t0 <= now) ++kept;
  steps_.resize(kept);
  for (const Footstep& s : steps) {
    Phase p;
    p.step = s;
    const int k = static_cast<int>(steps_.size());
    const double T = s.duration > 0 ? s.duration : options_.step_time;
    // a step that follows the previous one directly, or one that starts from standing
    const bool follows = k > 0 && steps_[k - 1].t_land >= now;
    p.t0 = follows ? steps_[k - 1].t_land
                   : std::max(now, k > 0 ? steps_[k - 1].t_land : t_start_) + options_.start_delay;
    p.zmp_from = Zmp(p.t0);  // the timeline so far: continuous
    // start_push: from standing the double support begins on the swinging sole (gait.h)
    if (!follows && options_.start_push) p.zmp_from = StancePoint(FeetAfter(k - 1), s.foot);
    // start_rock: half a single support on the swinging sole first (gait.h)
    p.hold = !follows && options_.start_rock;
    if (p.hold) p.zmp_from = StancePoint(FeetAfter(k - 1), s.foot);
    const double ds = follows ? options_.double_support_ratio * T
                      : p.hold ? 0.5 * (1 - options_.double_support_ratio) * T
                               : options_.start_time;
    p.t_lift = p.t0 + ds;
    p.t_land = p.t_lift + (1 - options_.double_support_ratio) * T;
    p.before = FeetAfter(k - 1);
    p.zmp_to = StancePoint(p.before, 1 - s.foot);
    // on a sole that bears only in part (across an edge), the ZMP goes to the middle of that part
    const Footstep* last = LastStepOf(1 - s.foot, k);
    if (last && last->contact_half.x() >= 0) {
      const double c = std::cos(last->yaw), sn = std::sin(last->yaw);
      const Eigen::Vector2d& d = last->contact_centre;
      p.zmp_to.head<2>() = last->p.head<2>() + Eigen::Vector2d(c * d.x() - sn * d.y(), sn * d.x() + c * d.y());
    }
    // a step down: the CoM comes down over the step as far as the landing leg needs to reach
    // the lower sole (the stance knee bends), the rest over the next step
    const double reach_xy = (s.p - p.before.p[1 - s.foot]).head<2>().norm();
    p.zmp_to.z() -= StepDownDrop(options_, p.zmp_to.z() - s.p.z(), reach_xy);
    // a step up onto a stair (an edge, not a slope): the CoM rises over the step as far as the
    // trailing leg still reaches, the rest over the next step
    if (IsStepEdge(p.before, s))
      p.zmp_to.z() += StepUpRise(options_, s.p.z() - p.zmp_to.z(), reach_xy);
    p.height = s.height >= 0 ? s.height : options_.step_height;
    p.detour = SwingDetour(p.before, s);
    steps_.push_back(p);
  }
  return kept;
}

Eigen::Vector2d Gait::SwingDetour(const FeetPose& before, const Footstep& step) const {
  if (!(options_.sole_half_length > 0) || !(options_.sole_half_width > 0)) return Eigen::Vector2d::Zero();
  StepLimits soles;
  soles.sole_half_size = Eigen::Vector2d(options_.sole_half_length, options_.sole_half_width);
  const int sw = step.foot, st = 1 - sw;
  const Eigen::Vector3d& a = before.p[sw];
  const Eigen::Vector3d& q = before.p[st];
  const double turn = WrapAngle(step.yaw - before.yaw[sw]);
  // outward: from the stance sole towards the swinging foot's side, in the stance sole's frame
  const Eigen::Vector2d n =
      Eigen::Rotation2Dd(before.yaw[st]) * Eigen::Vector2d(0, sw == kLeft ? 1.0 : -1.0);
  // the gap kept: the clearance, or what the ends have if they have less
  const double at_ends = std::min(SoleGap(a, before.yaw[sw], q, before.yaw[st], soles),
                                  SoleGap(step.p, step.yaw, q, before.yaw[st], soles));
  const double need = std::min(options_.swing_clearance, at_ends);
  for (double d = 0; d <= kMaxDetour + 1e-12; d += kDetourStep) {
    bool clear = true;
    for (int i = 1; i < kDetourSamples + 1 && clear; ++i) {
      const double f = static_cast<double>(i) / (kDetourSamples + 1);
      Eigen::Vector3d p = a + f * (step.p - a);
      p.head<2>() += std::sin(M_PI * f) * d * n;
      clear = SoleGap(p, before.yaw[sw] + f * turn, q, before.yaw[st], soles) >= need;
    }
    if (clear) return d * n;
  }
  return kMaxDetour * n;
}

bool Gait::AdjustLanding(int k, const Eigen::Vector2d& xy, double now) {
  if (k < 0 || k >= static_cast<int>(steps_.size())) return false;
  return AdjustStep(k, xy, steps_[k].t_land, false, now);
}

bool Gait::AdjustStep(int k, const Eigen::Vector2d& xy, double t_land, bool carry_later, double now) {
  if (k < 0 || k >= static_cast<int>(steps_.size())) return false;
  Phase& p = steps_[k];
  if (now < p.t_lift || now >= p.t_land) return false;
  if (!(t_land > now) || t_land > p.t_land) return false;
  GaitState s;
  At(now, &s);
  p.moved_from = s.feet.p[p.step.foot].head<2>();
  p.travel_from = Travel(p, now);
  if (t_land < p.t_land) {
    p.retime_phase = SwingPhase(p, now);
    p.retime_t = now;
    p.t_land = t_land;
  }
  const Eigen::Vector2d delta = xy - p.step.p.head<2>();
  p.step.p.head<2>() = xy;
  p.detour.setZero();
  // the later steps again, from the new stance and landing time (Replace keeps this one: it
  // has begun), moved with it when asked
  pending_.clear();
  for (size_t j = k + 1; j < steps_.size(); ++j) {
    pending_.push_back(steps_[j].step);
    if (carry_later) pending_.back().p.head<2>() += delta;
  }
  Replace(now, pending_);
  return true;
}

bool Gait::DelayLanding(int k, double delay, double now) {
  if (k < 0 || k >= static_cast<int>(steps_.size())) return false;
  Phase& p = steps_[k];
  if (now < p.t_lift || now >= p.t_land || !(delay > 0)) return false;
  p.retime_phase = SwingPhase(p, now);
  p.retime_t = now;
  p.t_land += delay;
  // the later steps again, from the later landing (Replace keeps this one: it has begun)
  pending_.clear();
  for (size_t j = k + 1; j < steps_.size(); ++j) pending_.push_back(steps_[j].step);
  Replace(now, pending_);
  return true;
}

}  // namespace ohrp::walking
