// Tests of the plans at a velocity and to a stop (robot_model/src/walking/plan_velocity.cc): the
// steps keep the limits, cover the commanded motion within one step, and end side by side.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "stances.h"
#include "walking/footsteps.h"

namespace ohrp::walking {
namespace {

constexpr double kTight = 1e-9;  // [m or rad] final stance

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

TEST(PlanVelocity, TheStrideGrowsAndShrinksByAtMostMaxStrideChange) {
  // 0.3 m strides (0.5 m/s at 0.6 s steps) from standing, by 5 cm a step: the mid frame's forward
  // increments are 0.05, 0.10, ... 0.30, ... 0.05; a foot lands the last two increments ahead of
  // where it stood (the first: the first increment), so its advance grows by at most 0.1 a step
  StepLimits l;
  l.max_forward = 0.3;
  l.max_stride_change = 0.05;
  const FeetPose start = Stance(l.width);
  std::string note;
  const double t = 0.6;
  const auto steps = PlanVelocity(start, 0.5, 0, 0, 12, t, l, &note);  // 20 steps and a closing one
  ASSERT_EQ(steps.size(), 21u);
  EXPECT_NE(note.find("max_stride_change"), std::string::npos) << note;
  EXPECT_EQ(CheckSteps(start, steps, l), "");
  auto advances = [](FeetPose feet, const std::vector<Footstep>& s) {
    std::vector<double> a;
    for (const Footstep& step : s) {
      a.push_back(step.p.x() - feet.p[step.foot].x());
      feet = After(feet, step);
    }
    return a;
  };
  const std::vector<double> a = advances(start, steps);
  EXPECT_NEAR(a[0], 0.05, 1e-9);
  for (size_t k = 1; k < a.size(); ++k) EXPECT_LE(std::abs(a[k] - a[k - 1]), 0.1 + 1e-9) << "step " << k;
  EXPECT_NEAR(*std::max_element(a.begin(), a.end()), 0.6, 1e-9);  // the full stride, both feet
  EXPECT_NEAR(a[19], 0.15, 1e-9);                                   // slowed down before the stop
  // without the limit the first foot goes the full stride at once
  l.max_stride_change = INFINITY;
  EXPECT_NEAR(advances(start, PlanVelocity(start, 0.5, 0, 0, 12, t, l, &note))[0], 0.3, 1e-9);
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

TEST(PlanVelocity, BadNumbersAreRefusedWithANote) {
  const StepLimits l;
  const FeetPose start = Stance(l.width);
  std::string note;
  EXPECT_TRUE(PlanVelocity(start, NAN, 0, 0, 4, 0.8, l, &note).empty());
  EXPECT_NE(note.find("finite"), std::string::npos) << note;
  EXPECT_TRUE(PlanVelocity(start, 0.1, 0, 0, 4, 0, l, &note).empty());
  EXPECT_NE(note.find("step_time > 0"), std::string::npos) << note;
  EXPECT_TRUE(PlanVelocity(start, 0.1, 0, 0, 0, 0.8, l, &note).empty());
  EXPECT_EQ(note, "");
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
  EXPECT_TRUE(PlanStop(end, 2, l).empty());
}

}  // namespace
}  // namespace ohrp::walking
