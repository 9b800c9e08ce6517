// Tests of the seeded random footsteps (robot_model/src/walking/plan_random.cc): every step keeps
// the limits, the same seed gives the same steps, the draws reach the corners of the limits
// (turns both ways, back steps, side steps out to the limit, stops), and the walk ends side by
// side.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "stances.h"
#include "walking/footsteps.h"

namespace ohrp::walking {
namespace {

// the landing of step k in the frame of the sole it steps from: x ahead, y outward, turn out
struct Relative {
  double x, y, turn;
};
Relative InStanceFrame(const FeetPose& feet, const Footstep& s) {
  const int stance = 1 - s.foot;
  const double side = s.foot == kLeft ? 1 : -1;
  const Eigen::Vector2d d = Eigen::Rotation2Dd(-feet.yaw[stance]) *
                            (s.p.head<2>() - feet.p[stance].head<2>());
  return {d.x(), side * d.y(), side * std::remainder(s.yaw - feet.yaw[stance], 2 * M_PI)};
}

TEST(PlanRandom, EveryStepKeepsTheLimitsAndTheWalkEndsSideBySide) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::string error;
    const auto steps = PlanRandom(start, 40, seed, l, 0.15, &error);
    ASSERT_EQ(error, "") << "seed " << seed;
    // 40, and a closing step unless the last was a stop
    ASSERT_GE(steps.size(), 40u) << "seed " << seed;
    ASSERT_LE(steps.size(), 41u) << "seed " << seed;
    EXPECT_EQ(CheckSteps(start, steps, l), "") << "seed " << seed;
    // side by side: the last sole beside the other at the width, parallel
    const FeetPose end = Apply(start, steps);
    const Relative r = InStanceFrame(Apply(start, {steps.begin(), steps.end() - 1}), steps.back());
    EXPECT_NEAR(r.x, 0, 1e-9) << "seed " << seed;
    EXPECT_NEAR(r.y, l.width, 1e-9) << "seed " << seed;
    EXPECT_NEAR(std::remainder(end.yaw[0] - end.yaw[1], 2 * M_PI), 0, 1e-9) << "seed " << seed;
  }
}

TEST(PlanRandom, TheSameSeedGivesTheSameStepsAndAnotherSeedOthers) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const auto a = PlanRandom(start, 30, 7, l), b = PlanRandom(start, 30, 7, l), c = PlanRandom(start, 30, 8, l);
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].foot, b[k].foot);
    EXPECT_EQ(a[k].p, b[k].p);
    EXPECT_EQ(a[k].yaw, b[k].yaw);
  }
  bool differ = a.size() != c.size();
  for (size_t k = 0; !differ && k < a.size(); ++k) differ = a[k].p != c[k].p;
  EXPECT_TRUE(differ);
}

TEST(PlanRandom, TheDrawsReachTheCornersOfTheLimits) {
  // over 400 steps: forward beyond 80 % of max_forward, back beyond 80 % of max_backward, out
  // beyond 80 % of width + max_side, turns out and in beyond 80 % of their limits, and stops
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const auto steps = PlanRandom(start, 400, 3, l, 0.15);
  double fwd = 0, back = 0, out = 0, turn_out = 0, turn_in = 0;
  int stops = 0;
  FeetPose feet = start;
  for (const Footstep& s : steps) {
    const Relative r = InStanceFrame(feet, s);
    fwd = std::max(fwd, r.x);
    back = std::max(back, -r.x);
    out = std::max(out, r.y);
    turn_out = std::max(turn_out, r.turn);
    turn_in = std::max(turn_in, -r.turn);
    if (std::abs(r.x) < 1e-9 && std::abs(r.y - l.width) < 1e-9 && std::abs(r.turn) < 1e-9) ++stops;
    feet = After(feet, s);
  }
  EXPECT_GT(fwd, 0.8 * l.max_forward);
  EXPECT_GT(back, 0.8 * l.max_backward);
  EXPECT_GT(out, 0.8 * (l.width + l.max_side));
  EXPECT_GT(turn_out, 0.8 * l.max_turn);
  EXPECT_GT(turn_in, 0.8 * l.max_turn_in);
  EXPECT_GT(stops, 400 * 0.15 / 2);  // about 60 expected
}

TEST(PlanRandom, BadInputIsRefusedWithAReason) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  std::string error;
  EXPECT_TRUE(PlanRandom(start, -1, 1, l, 0.15, &error).empty());
  EXPECT_NE(error.find("step count"), std::string::npos) << error;
  EXPECT_TRUE(PlanRandom(start, 10, 1, l, 1.5, &error).empty());
  EXPECT_NE(error.find("stops"), std::string::npos) << error;
  StepLimits bad = l;
  bad.max_forward = -1;
  EXPECT_TRUE(PlanRandom(start, 10, 1, bad, 0.15, &error).empty());
  EXPECT_FALSE(error.empty());
  error.clear();
  EXPECT_TRUE(PlanRandom(start, 0, 1, l, 0.15, &error).empty());  // nothing to walk
  EXPECT_EQ(error, "");
}

}  // namespace
}  // namespace ohrp::walking
