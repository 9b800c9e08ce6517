// A goal across the terrain, one level at a time (see terrain.h, TerrainMap::PlanGoalAcross).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "walking/terrain.h"

namespace ohrp::walking {
namespace {

constexpr double kAlongStep = 0.01;   // [m] spots tried along the heading
// [m] spots tried along the heading onto a level: finer than the run left on a 0.3 m tread for
// a 0.25 m sole between its heel's margin and its toes' clearance (5 mm)
constexpr double kPlaceStep = 0.0025;
constexpr double kRiseSample = 0.005; // [m] the terrain's height sampled along a step's way
constexpr int kMaxLevels = 200;       // level changes on one goal (a staircase of 200 stairs)

// the goal pose (x, y, yaw in the start's mid frame) in W
Frame2 GoalInWorld(const FeetPose& start, double x, double y, double yaw) {
  const Frame2 m = MidFrame(start);
  const double c = std::cos(m.yaw), s = std::sin(m.yaw);
  Frame2 g;
  g.p = m.p + Eigen::Vector3d(c * x - s * y, s * x + c * y, 0);
  g.yaw = m.yaw + yaw;
  return g;
}

// the goal relative to the mid frame of `feet` (x, y, yaw), the yaw the short way round
Eigen::Vector3d GoalFrom(const FeetPose& feet, const Frame2& goal) {
  const Frame2 m = MidFrame(feet);
  const Eigen::Vector3d d = goal.p - m.p;
  const double c = std::cos(m.yaw), s = std::sin(m.yaw);
  return {c * d.x() + s * d.y(), -s * d.x() + c * d.y(),
          std::remainder(goal.yaw - m.yaw, 2 * M_PI)};
}

}  // namespace

double TerrainMap::LargestRise(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  const Eigen::Rotation2Dd R0(yaw_);
  const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kRiseSample)));
  double largest = 0, last = 0;
  for (int i = 0; i <= n; ++i) {
    const Eigen::Vector2d q = origin_.head<2>() + R0 * (a + (b - a) * (static_cast<double>(i) / n));
    double h = 0;
    if (!Height(q.x(), q.y(), &h)) continue;  // no surface: the soles' own check says so
    if (i > 0) largest = std::max(largest, std::fabs(h - last));
    last = h;
  }
  return largest;
}

double TerrainMap::ToeClearance(const Footstep& s, const StepLimits& limits, double* need) const {
  const Eigen::Rotation2Dd R0(yaw_);
  const Eigen::Vector2d along(std::cos(s.yaw), std::sin(s.yaw)), across(-along.y(), along.x());
  const Eigen::Vector2d toe = s.p.head<2>() + limits.sole_half_size.x() * along;
  // the sole's plane (its surface's tilt: normal Rx(roll) Ry(pitch) e_z)
  const Eigen::Vector3d n = Eigen::AngleAxisd(s.roll, Eigen::Vector3d::UnitX()) *
                            Eigen::AngleAxisd(s.pitch, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  // the terrain's height above that plane `d` ahead of the toe on line `side` (-1, 0, 1: right
  // edge, centre, left edge); very low where there is none
  auto above = [&](double d, double side) {
    const Eigen::Vector2d p = toe + d * along + side * limits.sole_half_size.y() * across;
    const Eigen::Vector2d q = origin_.head<2>() + R0 * p;
    double h = 0;
    if (!Height(q.x(), q.y(), &h)) return -1e9;
    const Eigen::Vector2d off = p - s.p.head<2>();
    return h - origin_.z() - (s.p.z() - (n.x() * off.x() + n.y() * off.y()) / n.z());
  };
  if (need) *need = 0;
  const int n_samples = static_cast<int>(std::ceil(kToeReach / kRiseSample));
  for (int i = 0; i <= n_samples; ++i) {
    const double d = std::min(i * kRiseSample, kToeReach);
    for (double side : {-1.0, 0.0, 1.0}) {
      if (!(above(d, side) > kLevelChange)) continue;
      // the riser lies between the last sample clear of it and this one: bisected to 0.1 mm
      double lo = std::max(d - kRiseSample, 0.0), hi = d;
      for (int b = 0; b < 6 && i > 0; ++b) {
        const double mid = 0.5 * (lo + hi);
        (above(mid, side) > kLevelChange ? hi : lo) = mid;
      }
      if (need) *need = kShinLean * above(hi + 0.001, side);  // the riser's top, 1 mm behind its face
      return i == 0 ? 0.0 : lo;
    }
  }
  return kToeReach;
}

bool TerrainMap::ToesClear(const Footstep& s, const StepLimits& limits) const {
  double need = 0;
  return ToeClearance(s, limits, &need) >= need;
}

TerrainMap::LevelMargin TerrainMap::MarginFor(bool down) {
  // going down the toes may come to the next nose (it is a drop); the heel keeps off the nose
  return down ? LevelMargin{kLevelMargin, 0.0} : LevelMargin{kLevelMargin, kLevelMargin};
}

bool TerrainMap::OnOneLevel(const Footstep& s, const StepLimits& limits, const LevelMargin& margin,
                            SurfaceSample* out) const {
  const Eigen::Vector2d along(std::cos(s.yaw), std::sin(s.yaw));
  const Eigen::Vector2d centre = s.p.head<2>() + 0.5 * (margin.front - margin.back) * along;
  const Eigen::Vector2d half = limits.sole_half_size +
                               Eigen::Vector2d(0.5 * (margin.front + margin.back), kLevelMargin);
  std::string ignored;
  SurfaceSample wide;
  if (!SurfaceUnder(centre, s.yaw, half, &wide, &ignored) || !wide.planar) return false;
  return SurfaceUnder(s.p.head<2>(), s.yaw, limits.sole_half_size, out, &ignored);
}

bool TerrainMap::PlaceOnLevel(const FeetPose& feet, Footstep* s, const StepLimits& limits,
                              bool new_level, bool farthest, const LevelMargin* fixed) const {
  const Eigen::Vector2d stance = feet.p[1 - s->foot].head<2>();
  const double stance_z = feet.p[1 - s->foot].z();
  const Eigen::Vector2d along(std::cos(s->yaw), std::sin(s->yaw));
  const Footstep planned = *s;
  // `planned` moved by i spots along its heading, if it fits there
  auto at = [&](int i, Footstep* m) {
    *m = planned;
    m->p.head<2>() += i * kPlaceStep * along;
    SurfaceSample sample;
    std::string ignored;
    if (!SurfaceUnder(m->p.head<2>(), m->yaw, limits.sole_half_size, &sample, &ignored)) return false;
    const LevelMargin margin = fixed ? *fixed : MarginFor(sample.z < stance_z - kLevelChange);
    if (!OnOneLevel(*m, limits, margin, &sample)) return false;
    m->p.z() = sample.z;  // the rise is one of the limits
    m->roll = sample.roll;
    m->pitch = sample.pitch;
    if (!CheckStep(feet, *m, limits).empty()) return false;
    if (!ToesClear(*m, limits)) return false;
    if ((LargestRise(stance, m->p.head<2>()) > kLevelChange) != new_level) return false;
    // onto a new level from beside the other foot: the swing no longer than a stride
    return !new_level || (m->p - feet.p[m->foot]).head<2>().norm() <= limits.max_forward + 1e-9;
  };
  const int n = static_cast<int>(std::ceil((limits.max_forward + limits.max_backward +
                                            2 * limits.sole_half_size.x()) / kPlaceStep));
  Footstep m;
  for (int k = 0; k <= 2 * n; ++k) {
    // the farthest forward first, or the nearest the planned spot
    const int i = farthest ? n - k : (k % 2 ? (k + 1) / 2 : -k / 2);
    if (!at(i, &m)) continue;
    if (new_level) {
      // on a new level (a stair's tread), of the run of spots around it: up, the middle (the
      // toes as far from the next riser as the heel from the nose); down, the farthest (the
      // heel as far past the nose the foot comes down from as the stride allows)
      int lo = i, hi = i;
      Footstep other;
      while (lo > -n && at(lo - 1, &other)) --lo;
      while (hi < n && at(hi + 1, &other)) ++hi;
      const bool down = m.p.z() < feet.p[1 - m.foot].z();
      at(down ? hi : (lo + hi) / 2, &m);
    }
    *s = m;
    return true;
  }
  return false;
}

bool TerrainMap::SoleAcrossRise(const Footstep& s, const StepLimits& limits, double margin) const {
  const Eigen::Vector2d along(std::cos(s.yaw), std::sin(s.yaw)), across(-along.y(), along.x());
  const Eigen::Vector2d c = s.p.head<2>();
  const Eigen::Vector2d a = (limits.sole_half_size.x() + margin) * along;
  const Eigen::Vector2d b = (limits.sole_half_size.y() + margin) * across;
  return LargestRise(c - a, c + a) > kLevelChange || LargestRise(c - b, c + b) > kLevelChange;
}

bool TerrainMap::GoalOnOneLevel(Frame2* g, const StepLimits& limits) const {
  const Eigen::Vector2d along(std::cos(g->yaw), std::sin(g->yaw)), left(-along.y(), along.x());
  // both soles of the stance at `p`: on one level with the margin, their toes clear of a riser
  // (false with *missing when a sole has no surface under it)
  auto fits = [&](const Eigen::Vector3d& p, bool* missing) {
    *missing = false;
    for (int foot : {kLeft, kRight}) {
      Footstep s;
      s.foot = foot;
      s.yaw = g->yaw;
      s.p = p;
      s.p.head<2>() += (foot == kLeft ? 0.5 : -0.5) * limits.width * left;
      SurfaceSample sample;
      std::string ignored;
      if (!SurfaceUnder(s.p.head<2>(), s.yaw, limits.sole_half_size, &sample, &ignored)) {
        *missing = true;
        return false;
      }
      s.p.z() = sample.z;
      s.roll = sample.roll;
      s.pitch = sample.pitch;
      if (SoleAcrossRise(s, limits, kLevelMargin)) return false;
      if (!ToesClear(s, limits)) return false;
    }
    return true;
  };
  bool missing = false;
  // a goal off the terrain stays where it is: the plan names the step with no surface under it
  if (fits(g->p, &missing) || missing) return true;
  const int n = static_cast<int>(std::ceil(2 * limits.sole_half_size.x() / kAlongStep));
  for (int k = 1; k <= 2 * n; ++k) {
    const int i = k % 2 ? (k + 1) / 2 : -k / 2;  // the nearest first, forward before back
    Eigen::Vector3d p = g->p;
    p.head<2>() += i * kAlongStep * along;
    if (!fits(p, &missing)) continue;
    g->p = p;
    return true;
  }
  return false;
}

bool TerrainMap::CloseBeside(FeetPose* feet, const Footstep& last, const LevelMargin& margin,
                             const StepLimits& limits, std::vector<Footstep>* steps,
                             std::string* error) const {
  Footstep close = last;
  close.foot = 1 - last.foot;
  const Eigen::Vector2d left(-std::sin(last.yaw), std::cos(last.yaw));
  close.p.head<2>() += (close.foot == kLeft ? 1.0 : -1.0) * limits.width * left;
  if (!PlaceOnLevel(*feet, &close, limits, false, false, &margin)) {
    *error = "step " + std::to_string(steps->size() + 1) + " (" + SideName(close.foot) +
             "): no spot beside the other foot on its level (the whole sole and " +
             std::to_string(static_cast<int>(kLevelMargin * 1000)) + " mm around it)";
    return false;
  }
  steps->push_back(close);
  *feet = After(*feet, close);
  return true;
}

bool TerrainMap::PlanGoalAcross(const FeetPose& start, double x, double y, double yaw,
                                const StepLimits& limits, double search,
                                std::vector<Footstep>* steps, std::string* error,
                                std::string* note) const {
  steps->clear();
  Frame2 goal = GoalInWorld(start, x, y, yaw);
  const Frame2 asked = goal;
  if (!GoalOnOneLevel(&goal, limits)) {
    *error = "the goal's soles would rest across a rise (a stair's nose or riser) or within " +
             std::to_string(static_cast<int>(kLevelMargin * 1000)) + " mm of one, and no spot " +
             "within a sole's length along its heading rests on one level";
    return false;
  }
  if (note && (goal.p - asked.p).norm() > 1e-9) {
    const Eigen::Vector3d d = goal.p - asked.p;
    const bool ahead = d.x() * std::cos(goal.yaw) + d.y() * std::sin(goal.yaw) > 0;
    char buf[240];
    std::snprintf(buf, sizeof buf,
                  "the goal moved %.2f m %s along its heading: its soles would rest across a rise "
                  "(a stair's nose or riser) or within %d mm of one",
                  d.norm(), ahead ? "forward" : "back", static_cast<int>(kLevelMargin * 1000));
    *note = buf;
  }
  FeetPose feet = start;
  for (int level = 0; level <= kMaxLevels; ++level) {
    const Eigen::Vector3d rel = GoalFrom(feet, goal);
    std::string why;
    const std::vector<Footstep> plan = PlanToGoal(feet, rel.x(), rel.y(), rel.z(), limits, &why);
    if (!why.empty()) {
      *error = why;
      return false;
    }
    // the plan on the terrain until its first step onto another level or across a rise
    size_t k = 0;
    bool rise_on_way = false;
    for (; k < plan.size(); ++k) {
      SurfaceSample sample;
      if (!SurfaceUnder(plan[k].p.head<2>(), plan[k].yaw, limits.sole_half_size, &sample, &why)) {
        *error = "step " + std::to_string(steps->size() + 1) + " (" + SideName(plan[k].foot) + "): " + why;
        return false;
      }
      rise_on_way = LargestRise(feet.p[1 - plan[k].foot].head<2>(), plan[k].p.head<2>()) > kLevelChange;
      Footstep on = plan[k];
      on.p.z() = sample.z;
      on.roll = sample.roll;
      on.pitch = sample.pitch;
      if (rise_on_way || SoleAcrossRise(plan[k], limits) || !ToesClear(on, limits)) break;
      std::vector<Footstep> one = {plan[k]};
      if (k + 1 < plan.size()) one.push_back(plan[k + 1]);
      if (!PlaceSteps(&one, feet, limits, search, error)) return false;
      steps->push_back(one.front());
      feet = After(feet, one.front());
    }
    if (k == plan.size()) {  // at the goal on this level
      SetSwingClearance(steps, start, limits);
      return true;
    }
    // onto the next level: the step lands where its whole sole (and a margin) rests on the new
    // level, and the other foot closes beside it
    Footstep next = plan[k];
    if (rise_on_way && PlaceOnLevel(feet, &next, limits, true, false)) {
      const LevelMargin margin = MarginFor(next.p.z() < feet.p[1 - next.foot].z());
      steps->push_back(next);
      feet = After(feet, next);
      if (!CloseBeside(&feet, next, margin, limits, steps, error)) return false;
      continue;
    }
    // too far back (or a sole that would rest across the rise): both feet to the farthest spot
    // of this level first (its edge), then planned again from there
    const Frame2 before = MidFrame(feet);
    if (!PlaceOnLevel(feet, &next, limits, false, true)) {
      *error = "step " + std::to_string(steps->size() + 1) + " (" + SideName(next.foot) +
               "): no spot on this level within the limits to approach the next level from";
      return false;
    }
    steps->push_back(next);
    feet = After(feet, next);
    if (!CloseBeside(&feet, next, MarginFor(false), limits, steps, error)) return false;
    // the edge of this level must bring the feet nearer the goal: else they would go back and
    // forth across the rise (a goal beyond this level's edge that the next level does not lead to)
    const double to_goal = (goal.p - before.p).head<2>().norm();
    if ((MidFrame(feet).p - before.p).head<2>().norm() >= kAlongStep &&
        (goal.p - MidFrame(feet).p).head<2>().norm() >= to_goal) {
      *error = "step " + std::to_string(steps->size()) + " (" + SideName(next.foot) +
               "): the way to the goal crosses a rise that no step within the limits leads over "
               "from this level (its edge is no nearer the goal)";
      return false;
    }
    if ((MidFrame(feet).p - before.p).head<2>().norm() < kAlongStep) {
      *error = "step " + std::to_string(steps->size() + 1) + " (" + SideName(next.foot) +
               "): the next level has no spot for the whole sole (and " +
               std::to_string(static_cast<int>(kLevelMargin * 1000)) + " mm around it) within " +
               "max_forward " + std::to_string(limits.max_forward).substr(0, 5) +
               " m of the feet at the edge of this level: a longer max_forward (walk --params), "
               "or a deeper tread";
      return false;
    }
  }
  *error = "more than " + std::to_string(kMaxLevels) + " changes of level on the way to the goal";
  return false;
}

}  // namespace ohrp::walking
