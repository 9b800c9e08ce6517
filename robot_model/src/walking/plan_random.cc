// A seeded random footstep sequence within the step limits (see walking/footsteps.h): the test
// of "any footsteps within the limits" that nobody picked by hand.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "plan_walk.h"
#include "step_geometry.h"

namespace ohrp::walking {
namespace {

constexpr int kTries = 100;  // draws of one step before the stance is declared a dead end

// a step by `foot` drawn uniformly within the planar limits, in the stance sole's frame
Footstep Draw(const FeetPose& feet, int foot, const StepLimits& l, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int stance = 1 - foot;
  const double side = SideSign(foot);
  const double x = -l.max_backward + u(*rng) * (l.max_backward + l.max_forward);
  const double y = l.min_width + u(*rng) * (l.width + l.max_side - l.min_width);
  const double turn = -l.max_turn_in + u(*rng) * (l.max_turn_in + l.max_turn);
  Footstep s;
  s.foot = foot;
  const Eigen::Vector2d xy = feet.p[stance].head<2>() +
                             Eigen::Rotation2Dd(feet.yaw[stance]) * Eigen::Vector2d(x, side * y);
  s.p = Eigen::Vector3d(xy.x(), xy.y(), feet.p[stance].z());
  s.yaw = WrapAngle(feet.yaw[stance] + side * turn);
  return s;
}

}  // namespace

std::vector<Footstep> PlanRandom(const FeetPose& start, int count, unsigned seed,
                                 const StepLimits& l, double stop_share, std::string* error) {
  auto refuse = [&](const std::string& why) {
    if (error) *error = why;
    return std::vector<Footstep>{};
  };
  if (count < 0 || count > kMaxSteps)
    return refuse("the step count must be in [0, " + std::to_string(kMaxSteps) + "]");
  if (!(stop_share >= 0 && stop_share <= 1)) return refuse("the share of stops must be in [0, 1]");
  if (const std::string bad = CheckLimits(l); !bad.empty()) return refuse(bad);
  if (const std::string stance = StanceProblem(start, l); !stance.empty()) return refuse(stance);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Footstep> steps;
  FeetPose feet = start;
  int foot = u(rng) < 0.5 ? kLeft : kRight;
  int last = -1;
  for (int k = 0; k < count; ++k) {
    // a stop: the other foot closes beside the last one (set within the limits if it must)
    if (last >= 0 && u(rng) < stop_share) {
      std::vector<Footstep> close = PlanStop(feet, last, l);
      if (!close.empty()) {
        Footstep s = close.front();
        FitStep(feet, &s, l);
        if (CheckStep(feet, s, l).empty()) {
          steps.push_back(s);
          feet = After(feet, s);
          last = s.foot;
          foot = 1 - last;
          continue;
        }
      }
    }
    bool found = false;
    for (int t = 0; t < kTries && !found; ++t) {
      Footstep s = Draw(feet, foot, l, &rng);
      FitStep(feet, &s, l);  // the soles' clearance: set out sideways the least
      if (!CheckStep(feet, s, l).empty()) continue;
      steps.push_back(s);
      feet = After(feet, s);
      found = true;
    }
    if (!found) return refuse("no step within the limits found from step " + std::to_string(k + 1));
    last = foot;
    foot = 1 - foot;
  }
  // the feet side by side at the end
  if (last >= 0) {
    std::vector<Footstep> close = PlanStop(feet, last, l);
    for (Footstep& s : close) {
      FitStep(feet, &s, l);
      if (!CheckStep(feet, s, l).empty()) return refuse("the closing step breaks the limits");
      steps.push_back(s);
      feet = After(feet, s);
    }
  }
  return steps;
}

}  // namespace ohrp::walking
