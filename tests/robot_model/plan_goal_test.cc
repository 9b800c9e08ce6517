// Tests of the plans to a goal (robot_model/src/walking/plan_goal.cc, plan_walk.cc): every
// planned step keeps the limits, the step counts are the least the limits allow (closed forms
// stated in each test) and the walks end side by side at the goal.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "stances.h"
#include "walking/footsteps.h"

namespace ohrp::walking {
namespace {

constexpr double kTight = 1e-9;  // [m or rad] final stance against the goal

// the steps keep the limits, alternate, and end side by side at `width` about the goal
void ExpectWalkTo(const FeetPose& start, const std::vector<Footstep>& steps, double x, double y,
                  double yaw, const StepLimits& l) {
  ASSERT_FALSE(steps.empty());
  EXPECT_EQ(CheckSteps(start, steps, l), "");
  for (size_t k = 1; k < steps.size(); ++k) EXPECT_NE(steps[k].foot, steps[k - 1].foot) << k;
  const FeetPose end = Apply(start, steps);
  const Frame2 m = MidFrame(end);
  EXPECT_NEAR(m.p.x(), x, kTight);
  EXPECT_NEAR(m.p.y(), y, kTight);
  EXPECT_NEAR(std::remainder(m.yaw - yaw, 2 * M_PI), 0, kTight);
  EXPECT_NEAR(end.yaw[kLeft], end.yaw[kRight], kTight);
  EXPECT_NEAR((end.p[kLeft] - end.p[kRight]).norm(), l.width, kTight);
  // the left sole on the left of the mid frame
  const Eigen::Vector2d left = end.p[kLeft].head<2>() - m.p.head<2>();
  EXPECT_GT(-std::sin(m.yaw) * left.x() + std::cos(m.yaw) * left.y(), 0);
}

// the least n with ceil(n/2) * lead + floor(n/2) * trail >= need: the walking steps when the
// leading foot may gain `lead` and the trailing foot `trail` per step
int LeastSteps(double need, double lead, double trail) {
  int n = 0;
  while (std::ceil(n / 2.0) * lead + std::floor(n / 2.0) * trail < need - 1e-12) ++n;
  return n;
}

//---------------- plans to a goal ----------------

TEST(PlanToGoal, TenMetresStraightTakeDistanceOverMaxForwardPlusAClosingStep) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 10, 0, 0, l);
  // each step lands at most max_forward ahead of the other foot: ceil(10 / 0.25) = 40, + 1 closing
  EXPECT_EQ(steps.size(), static_cast<size_t>(std::ceil(10 / l.max_forward)) + 1);
  ExpectWalkTo(start, steps, 10, 0, 0, l);
}

// the default limits with the soles' clearance set (the closed forms of these tests are worked
// out for it)
StepLimits Clearance(double c) {
  StepLimits l;
  l.clearance = c;
  return l;
}

TEST(PlanToGoal, OneMetreSidewaysLeadsWithTheLeftFoot) {
  const StepLimits l = Clearance(0.01);  // the counts below are for a 1 cm gap
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 0, 1, 0, l);
  // the left (outward) foot gains max_side = 0.10 per step, the right (inward) foot what min_width
  // and the soles' clearance leave: width - max(min_width, 2 * 0.065 + 0.01) = 0.02; 17 + 1 closing
  const double inward = l.width - std::max(l.min_width, 2 * l.sole_half_size.y() + l.clearance);
  const int n = LeastSteps(1.0, l.max_side, inward);
  EXPECT_EQ(n, 17);
  EXPECT_EQ(steps.size(), static_cast<size_t>(n + 1));
  EXPECT_EQ(steps.front().foot, kLeft);
  ExpectWalkTo(start, steps, 0, 1, 0, l);
}

TEST(PlanToGoal, OneMetreToTheRightLeadsWithTheRightFoot) {
  const StepLimits l = Clearance(0.01);  // the counts below are for a 1 cm gap
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 0, -1, 0, l);
  EXPECT_EQ(steps.size(), 18u);
  EXPECT_EQ(steps.front().foot, kRight);
  ExpectWalkTo(start, steps, 0, -1, 0, l);
}

TEST(PlanToGoal, HalfTurnOnTheSpotTakesTheTurnLimitsOfBothFeet) {
  const StepLimits l = Clearance(0.01);  // the counts below are for a 1 cm gap
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 0, 0, M_PI, l);
  // the left foot turns out by max_turn, the right foot in by max_turn_in: pi needs 13, + 1 closing
  const int n = LeastSteps(M_PI, l.max_turn, l.max_turn_in);
  EXPECT_EQ(n, 13);
  EXPECT_EQ(steps.size(), static_cast<size_t>(n + 1));
  EXPECT_EQ(steps.front().foot, kLeft);
  ExpectWalkTo(start, steps, 0, 0, M_PI, l);
}

TEST(PlanToGoal, QuarterTurnToTheRightLeadsWithTheRightFoot) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 0, 0, -M_PI / 2, l);
  EXPECT_EQ(steps.size(), static_cast<size_t>(LeastSteps(M_PI / 2, l.max_turn, l.max_turn_in) + 1));
  EXPECT_EQ(steps.front().foot, kRight);
  ExpectWalkTo(start, steps, 0, 0, -M_PI / 2, l);
}

TEST(PlanToGoal, DiagonalGoalWithATurnIsBoundByTheTurn) {
  const StepLimits l = Clearance(0.01);  // the counts below are for a 1 cm gap
  const FeetPose start = Stance(l.width);
  // (0.5, 0.5, 90 deg): a quarter circle of radius 0.5 m, 0.79 m long: 4 steps of max_forward
  // would do; the turn needs 7 (3 pairs of 0.35 + 0.15 rad = 1.5 < pi/2), + 1 closing
  const int n = LeastSteps(M_PI / 2, l.max_turn, l.max_turn_in);
  EXPECT_EQ(n, 7);
  EXPECT_GT(n, std::ceil(M_PI / 4 / l.max_forward));
  const auto steps = PlanToGoal(start, 0.5, 0.5, M_PI / 2, l);
  EXPECT_EQ(steps.size(), static_cast<size_t>(n + 1));
  EXPECT_EQ(steps.front().foot, kLeft);
  ExpectWalkTo(start, steps, 0.5, 0.5, M_PI / 2, l);
}

TEST(PlanToGoal, GoalInTheStartMidFrameOfATurnedStance) {
  StepLimits l;
  l.width = 0.18;  // HRP-1S: sole centres at y = +-0.09, soles 0.25 x 0.14 m
  l.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  const double yaw0 = 0.7;
  const FeetPose start = Stance(l.width, 1.0, -2.0, yaw0);
  const auto steps = PlanToGoal(start, 2.0, -0.5, -1.0, l);
  // the goal in W: the start's mid frame moved by (2, -0.5) in its own frame
  const double gx = 1.0 + 2.0 * std::cos(yaw0) + 0.5 * std::sin(yaw0);
  const double gy = -2.0 + 2.0 * std::sin(yaw0) - 0.5 * std::cos(yaw0);
  ExpectWalkTo(start, steps, gx, gy, yaw0 - 1.0, l);
}

TEST(PlanToGoal, NoGoalNoSteps) {
  const StepLimits l;
  std::string error = "x";
  EXPECT_TRUE(PlanToGoal(Stance(l.width), 0, 0, 0, l, &error).empty());
  EXPECT_EQ(error, "");
}

TEST(PlanToGoal, ACrossedStartIsRefusedWithTheReason) {
  const StepLimits l;
  FeetPose start = Stance(l.width);
  std::swap(start.p[kLeft], start.p[kRight]);
  std::string error;
  EXPECT_TRUE(PlanToGoal(start, 1, 0, 0, l, &error).empty());
  EXPECT_NE(error.find("cross"), std::string::npos) << error;
}

TEST(PlanToGoal, AnyGoalIsReachedWithinTheLimits) {
  // goals spread over +-6 m, +-2 m, +-pi (a fixed sequence): default limits from a stance at their
  // width and from HRP-1S's wider one (0.18 m), and HRP-1S's own limits
  StepLimits hrp1s;
  hrp1s.width = 0.18;
  hrp1s.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  std::mt19937 random(7);
  auto uniform = [&](double a) { return std::uniform_real_distribution<double>(-a, a)(random); };
  for (const auto& [l, width] :
       {std::pair(StepLimits(), 0.16), std::pair(StepLimits(), 0.18), std::pair(hrp1s, 0.18)})
    for (int i = 0; i < 150; ++i) {
      const double x = uniform(6), y = uniform(2), yaw = uniform(M_PI);
      const FeetPose start = Stance(width);
      std::string error;
      const auto steps = PlanToGoal(start, x, y, yaw, l, &error);
      SCOPED_TRACE(testing::Message() << "goal " << x << ", " << y << ", " << yaw << ": " << error);
      ExpectWalkTo(start, steps, x, y, yaw, l);
      // never fewer than the turn alone needs; never more than turning, side-stepping and walking
      // one after the other would (each its least count, + 1 closing)
      const double inward = l.width - std::max(l.min_width, 2 * l.sole_half_size.y() + l.clearance);
      const int apart =
          static_cast<int>(std::ceil(std::abs(x) / (x > 0 ? l.max_forward : l.max_backward))) +
          LeastSteps(std::abs(y), l.max_side, inward) +
          LeastSteps(std::abs(yaw), l.max_turn, l.max_turn_in) + 1;
      EXPECT_GE(steps.size(), LeastSteps(std::abs(yaw), l.max_turn, l.max_turn_in) + 1u);
      EXPECT_LE(steps.size(), static_cast<size_t>(apart));
    }
}

}  // namespace
}  // namespace ohrp::walking
