// Tests of the footstep plans (robot_model/src/walking/plan.cc): every
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

TEST(PlanToGoal, OneMetreSidewaysLeadsWithTheLeftFoot) {
  const StepLimits l;
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
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const auto steps = PlanToGoal(start, 0, -1, 0, l);
  EXPECT_EQ(steps.size(), 18u);
  EXPECT_EQ(steps.front().foot, kRight);
  ExpectWalkTo(start, steps, 0, -1, 0, l);
}

TEST(PlanToGoal, HalfTurnOnTheSpotTakesTheTurnLimitsOfBothFeet) {
  const StepLimits l;
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
  const StepLimits l;
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
  // goals spread over +-3 m, +-2 m, +-pi (a fixed sequence), default and HRP-1S limits
  StepLimits hrp1s;
  hrp1s.width = 0.18;
  hrp1s.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  std::mt19937 random(7);
  auto uniform = [&](double a) { return std::uniform_real_distribution<double>(-a, a)(random); };
  for (const StepLimits& l : {StepLimits(), hrp1s})
    for (int i = 0; i < 200; ++i) {
      const double x = uniform(3), y = uniform(2), yaw = uniform(M_PI);
      const FeetPose start = Stance(l.width);
      std::string error;
      const auto steps = PlanToGoal(start, x, y, yaw, l, &error);
      SCOPED_TRACE(testing::Message() << "goal " << x << ", " << y << ", " << yaw << ": " << error);
      ExpectWalkTo(start, steps, x, y, yaw, l);
      // never fewer than the turn alone needs
      EXPECT_GE(steps.size(), LeastSteps(std::abs(yaw), l.max_turn, l.max_turn_in) + 1u);
    }
}

//---------------- velocity and stop ----------------

TEST(PlanVelocity, CoversTheCommandedDistanceWithinOneStep) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const double vx = 0.2, time = 10, t = 0.8;  // [m/s, s, s]
  std::string note = "x";
  const auto steps = PlanVelocity(start, vx, 0, 0, time, t, l, &note);
  EXPECT_EQ(note, "");
  EXPECT_EQ(steps.size(), static_cast<size_t>(std::lround(time / t)) + 1);
  EXPECT_EQ(CheckSteps(start, steps, l), "");
  for (const auto& s : steps) EXPECT_EQ(s.duration, t);
  const Frame2 m = MidFrame(Apply(start, steps));
  EXPECT_NEAR(m.p.x(), vx * time, vx * t);
  EXPECT_NEAR(m.p.y(), 0, kTight);
}

TEST(PlanVelocity, TurningWalkCoversTheTurnWithinOneStep) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  const double vx = 0.1, vy = 0.02, wz = 0.25, time = 8, t = 0.8;
  std::string note;
  const auto steps = PlanVelocity(start, vx, vy, wz, time, t, l, &note);
  EXPECT_EQ(note, "");
  EXPECT_EQ(CheckSteps(start, steps, l), "");
  EXPECT_EQ(steps.front().foot, kLeft);
  // a pair of steps turns 2 wz t: the yaw after n steps is within one step's turn of wz time
  EXPECT_NEAR(MidFrame(Apply(start, steps)).yaw, wz * time, l.max_turn);
}

TEST(PlanVelocity, ATooFastCommandIsReducedToTheLimitsAndSaysSo) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  std::string note;
  const auto steps = PlanVelocity(start, 1.0, 0, 0, 4, 0.5, l, &note);
  EXPECT_NE(note.find("vx 1.000"), std::string::npos) << note;
  EXPECT_NE(note.find("max_forward"), std::string::npos) << note;
  EXPECT_EQ(CheckSteps(start, steps, l), "");
  // 8 steps of max_forward, then the closing step
  EXPECT_NEAR(MidFrame(Apply(start, steps)).p.x(), 8 * l.max_forward, kTight);
}

TEST(PlanVelocity, AnyVelocityGivesStepsWithinTheLimits) {
  // velocities up to and beyond the limits (a fixed sequence): reduced where needed, never refused
  const StepLimits l;
  std::mt19937 random(11);
  auto uniform = [&](double a) { return std::uniform_real_distribution<double>(-a, a)(random); };
  for (int i = 0; i < 200; ++i) {
    const double vx = uniform(0.5), vy = uniform(0.2), wz = uniform(0.6);
    const FeetPose start = Stance(l.width);
    std::string note;
    const auto steps = PlanVelocity(start, vx, vy, wz, 4, 0.8, l, &note);
    SCOPED_TRACE(testing::Message() << "v " << vx << ", " << vy << ", " << wz << ": " << note);
    ASSERT_GE(steps.size(), 6u);
    EXPECT_EQ(CheckSteps(start, steps, l), "");
    const FeetPose end = Apply(start, steps);
    EXPECT_NEAR((end.p[kLeft] - end.p[kRight]).norm(), l.width, kTight);
  }
}

TEST(PlanStop, TheOtherFootClosesBesideTheLastOne) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  auto walk = PlanVelocity(start, 0.15, 0, 0.2, 4, 0.8, l);
  walk.pop_back();  // stopped before its own closing step
  const FeetPose feet = Apply(start, walk);
  const int last = walk.back().foot;
  const auto stop = PlanStop(feet, last, l);
  ASSERT_EQ(stop.size(), 1u);
  EXPECT_EQ(stop[0].foot, 1 - last);
  EXPECT_EQ(CheckStep(feet, stop[0], l), "");
  const FeetPose end = After(feet, stop[0]);
  EXPECT_NEAR((end.p[kLeft] - end.p[kRight]).norm(), l.width, kTight);
  EXPECT_NEAR(end.yaw[kLeft], end.yaw[kRight], kTight);
  EXPECT_TRUE(PlanStop(end, 1 - last, l).empty());
}

}  // namespace
}  // namespace ohrp::walking
