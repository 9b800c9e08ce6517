// Tests of the footstep limits (robot_model/src/walking/footsteps.cc): each limit of CheckStep
// passes a step on it and refuses one beyond it, naming the limit; the sole gap against closed
// forms; the mid frame.
#include "walking/footsteps.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "stances.h"

namespace ohrp::walking {
namespace {

// a step of `foot` at (x, lateral outward of the stance foot, yaw turned out) from a stance of
// default width at the origin (the stance foot at y = -+width/2)
Footstep Landing(int foot, double x, double lateral, double turn_out, const StepLimits& l) {
  const double out = foot == kLeft ? 1 : -1;
  Footstep s;
  s.foot = foot;
  s.p = Eigen::Vector3d(x, -out * 0.5 * l.width + out * lateral, 0);
  s.yaw = out * turn_out;
  return s;
}

// the step on the limit passes; the one beyond fails with a message holding `limit`
void ExpectLimit(double on, double beyond, const char* limit,
                 Footstep (*make)(int, double, const StepLimits&), const StepLimits& l) {
  for (int foot : {kLeft, kRight}) {
    const FeetPose feet = Stance(l.width);
    EXPECT_EQ(CheckStep(feet, make(foot, on, l), l), "") << SideName(foot) << " at " << on;
    const std::string why = CheckStep(feet, make(foot, beyond, l), l);
    EXPECT_NE(why.find(limit), std::string::npos)
        << SideName(foot) << " at " << beyond << ": " << why;
  }
}

TEST(CheckStep, RefusesBeyondMaxForward) {
  const StepLimits l;
  ExpectLimit(
      l.max_forward, l.max_forward + 0.01, "max_forward",
      [](int f, double v, const StepLimits& l) { return Landing(f, v, l.width, 0, l); }, l);
}

TEST(CheckStep, RefusesBeyondMaxBackward) {
  const StepLimits l;
  ExpectLimit(
      -l.max_backward, -l.max_backward - 0.01, "max_backward",
      [](int f, double v, const StepLimits& l) { return Landing(f, v, l.width, 0, l); }, l);
}

TEST(CheckStep, RefusesBeyondMaxSide) {
  const StepLimits l;
  ExpectLimit(
      l.width + l.max_side, l.width + l.max_side + 0.01, "max_side",
      [](int f, double v, const StepLimits& l) { return Landing(f, 0, v, 0, l); }, l);
}

TEST(CheckStep, RefusesInsideMinWidth) {
  StepLimits l;
  l.sole_half_size.y() = 0.05;  // narrow soles: min_width binds before the clearance
  ExpectLimit(
      l.min_width, l.min_width - 0.01, "min_width",
      [](int f, double v, const StepLimits& l) { return Landing(f, 0, v, 0, l); }, l);
}

TEST(CheckStep, RefusesBeyondMaxTurnOut) {
  const StepLimits l;
  ExpectLimit(
      l.max_turn, l.max_turn + 0.01, "max_turn",
      [](int f, double v, const StepLimits& l) { return Landing(f, 0, 0.24, v, l); }, l);
}

TEST(CheckStep, RefusesBeyondMaxTurnIn) {
  const StepLimits l;
  ExpectLimit(
      -l.max_turn_in, -l.max_turn_in - 0.01, "max_turn_in",
      [](int f, double v, const StepLimits& l) { return Landing(f, 0, 0.24, v, l); }, l);
}

TEST(CheckStep, RefusesSolesCloserThanTheClearance) {
  const StepLimits l;
  // parallel soles side by side: the gap is the lateral distance less a sole's width
  const double touching = 2 * l.sole_half_size.y() + l.clearance;
  ExpectLimit(
      touching, touching - 0.002, "clearance",
      [](int f, double v, const StepLimits& l) { return Landing(f, 0, v, 0, l); }, l);
}

TEST(CheckStep, RefusesCrossingFeet) {
  const StepLimits l;
  for (int foot : {kLeft, kRight}) {
    // the landing foot on the far side of the stance foot
    const std::string why = CheckStep(Stance(l.width), Landing(foot, 0, -0.05, 0, l), l);
    EXPECT_NE(why.find("cross"), std::string::npos) << why;
  }
}

TEST(CheckStep, MeasuresInTheStanceFootsFrame) {
  const StepLimits l;
  // the whole stance turned by 90 deg: a step along +y world is forward
  const FeetPose feet = Stance(l.width, 0, 0, M_PI / 2);
  Footstep s;
  s.foot = kLeft;
  s.yaw = M_PI / 2;
  s.p = feet.p[kRight] + Eigen::Vector3d(-l.width, l.max_forward + 0.01, 0);
  EXPECT_NE(CheckStep(feet, s, l).find("max_forward"), std::string::npos);
  s.p.y() -= 0.02;
  EXPECT_EQ(CheckStep(feet, s, l), "");
}

TEST(CheckSteps, NamesTheFirstFailingStep) {
  const StepLimits l;
  const std::vector<Footstep> steps = {Landing(kLeft, 0.2, l.width, 0, l),
                                       Landing(kRight, 0.4, l.width, 0, l),
                                       Landing(kLeft, 0.9, l.width, 0, l)};
  const std::string why = CheckSteps(Stance(l.width), steps, l);
  EXPECT_EQ(why.rfind("step 3 (left): ", 0), 0u) << why;
  EXPECT_NE(why.find("max_forward"), std::string::npos) << why;
}

TEST(CheckLimits, RefusesMinWidthAboveWidth) {
  StepLimits l;
  EXPECT_EQ(CheckLimits(l), "");
  l.min_width = 0.2;
  EXPECT_NE(CheckLimits(l).find("min_width"), std::string::npos);
}

//---------------- geometry ----------------

TEST(SoleGap, MatchesClosedForms) {
  const StepLimits l;
  const double hx = l.sole_half_size.x(), hy = l.sole_half_size.y();
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  // side by side, in line, one turned by 90 deg ahead, the same place
  EXPECT_NEAR(SoleGap(Eigen::Vector3d(0, 0.2, 0), 0, o, 0, l), 0.2 - 2 * hy, 1e-12);
  EXPECT_NEAR(SoleGap(Eigen::Vector3d(0.3, 0, 0), 0, o, 0, l), 0.3 - 2 * hx, 1e-12);
  EXPECT_NEAR(SoleGap(Eigen::Vector3d(0.3, 0, 0), M_PI / 2, o, 0, l), 0.3 - hx - hy, 1e-12);
  EXPECT_NEAR(SoleGap(o, 0, o, 0, l), -2 * hy, 1e-12);
  // corner to corner along the diagonal: the distance between the nearest corners
  const Eigen::Vector3d diag(2 * hx + 0.03, 2 * hy + 0.04, 0);
  EXPECT_NEAR(SoleGap(diag, 0, o, 0, l), 0.05, 1e-12);
}

// FitStep: a step within the limits is left as it is; one beyond a limit comes back onto it, the
// least move (checked against CheckStep and the sole gap's closed form)
TEST(FitStep, LeavesAStepWithinTheLimitsAlone) {
  const StepLimits l;
  for (int foot : {kLeft, kRight}) {
    for (const Footstep& s : {Landing(foot, 0.1, l.width, 0, l),
                              Landing(foot, l.max_forward, l.width + l.max_side, l.max_turn, l)}) {
      ASSERT_EQ(CheckStep(Stance(l.width), s, l), "");
      Footstep fitted = s;
      EXPECT_EQ(FitStep(Stance(l.width), &fitted, l), 0.0);
      EXPECT_EQ(fitted.p, s.p);
      EXPECT_EQ(fitted.yaw, s.yaw);
    }
  }
}

TEST(FitStep, ClampsForwardBackwardTurnAndWidth) {
  const StepLimits l;
  const FeetPose feet = Stance(l.width);
  for (int foot : {kLeft, kRight}) {
    const double out = foot == kLeft ? 1 : -1;
    Footstep s = Landing(foot, l.max_forward + 0.05, l.width, 0, l);
    EXPECT_NEAR(FitStep(feet, &s, l), 0.05, 1e-12);
    EXPECT_NEAR(s.p.x(), l.max_forward, 1e-12);
    s = Landing(foot, -l.max_backward - 0.03, l.width, 0, l);
    EXPECT_NEAR(FitStep(feet, &s, l), 0.03, 1e-12);
    EXPECT_NEAR(s.p.x(), -l.max_backward, 1e-12);
    s = Landing(foot, 0, l.width + l.max_side + 0.04, 0, l);
    EXPECT_NEAR(FitStep(feet, &s, l), 0.04, 1e-12);
    EXPECT_NEAR(out * (s.p.y() - feet.p[1 - foot].y()), l.width + l.max_side, 1e-12);
    // toes in beyond max_turn_in (well apart: only the turn is out of the limits)
    s = Landing(foot, 0, l.width + 0.05, -l.max_turn_in - 0.1, l);
    EXPECT_NEAR(FitStep(feet, &s, l), 0.0, 1e-12);  // the sole did not move, it turned
    EXPECT_NEAR(out * s.yaw, -l.max_turn_in, 1e-12);
    EXPECT_EQ(CheckStep(feet, s, l), "") << SideName(foot);
  }
}

TEST(FitStep, SetsASoleOnTheStanceSoleOutByTheLeastShift) {
  // the closing step of the walk on the 5 deg slope (HRP-1S: soles 0.25 x 0.14 m, width 0.18 m)
  // as its plan frame's correction put it: 138 mm beside the right sole, toes in 3.5 deg, the
  // soles overlapping by 9 mm
  StepLimits l;
  l.width = 0.18;
  l.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  FeetPose feet = Stance(l.width);
  feet.p[kRight] = Eigen::Vector3d(5.16237, 0.208331, 0);
  feet.yaw[kRight] = 0.0381;
  Footstep s;
  s.foot = kLeft;
  s.p = Eigen::Vector3d(5.15069, 0.346431, 0.01);
  s.yaw = -0.0223;
  const double before = SoleGap(s.p, s.yaw, feet.p[kRight], feet.yaw[kRight], l);
  EXPECT_NEAR(before, -0.009, 0.0005);
  EXPECT_NE(CheckStep(feet, s, l).find("clearance"), std::string::npos);
  const Footstep planned = s;
  const double moved = FitStep(feet, &s, l);
  EXPECT_EQ(CheckStep(feet, s, l), "");
  // the least shift: the gap is the clearance; only sideways (in the stance sole's frame), the
  // yaw and the height kept
  EXPECT_NEAR(SoleGap(s.p, s.yaw, feet.p[kRight], feet.yaw[kRight], l), l.clearance, 1e-6);
  const Eigen::Vector2d d0 = Eigen::Rotation2Dd(-feet.yaw[kRight]) * (planned.p - feet.p[kRight]).head<2>();
  const Eigen::Vector2d d1 = Eigen::Rotation2Dd(-feet.yaw[kRight]) * (s.p - feet.p[kRight]).head<2>();
  EXPECT_NEAR(d1.x(), d0.x(), 1e-9);
  EXPECT_GT(d1.y(), d0.y());
  EXPECT_NEAR(moved, d1.y() - d0.y(), 1e-9);
  EXPECT_NEAR(moved, (s.p - planned.p).norm(), 1e-9);
  // about the overlap (9 mm) and the clearance, less the turn's share
  EXPECT_GT(moved, 0.009 + l.clearance - 0.004);
  EXPECT_LT(moved, 0.009 + l.clearance + 0.006);
  EXPECT_EQ(s.yaw, planned.yaw);
  EXPECT_EQ(s.p.z(), planned.p.z());
}

TEST(FitStep, TurnsTheSoleParallelWhenNoLateralPlaceClearsIt) {
  // the soles side by side at exactly their width plus the clearance, no side step: a sole
  // turned toes in ahead of the stance sole touches it wherever it goes sideways
  StepLimits l;
  l.width = 2 * l.sole_half_size.y() + l.clearance;
  l.max_side = 0;
  for (int foot : {kLeft, kRight}) {
    const double out = foot == kLeft ? 1 : -1;
    const FeetPose feet = Stance(l.width);
    Footstep s = Landing(foot, 0.1, l.width, -l.max_turn_in, l);
    ASSERT_NE(CheckStep(feet, s, l).find("clearance"), std::string::npos);
    FitStep(feet, &s, l);
    EXPECT_EQ(s.yaw, feet.yaw[1 - foot]) << SideName(foot);
    EXPECT_NEAR(out * (s.p.y() - feet.p[1 - foot].y()), l.width, 1e-9);
    EXPECT_EQ(CheckStep(feet, s, l), "") << SideName(foot);
  }
}

TEST(MidFrame, AveragesTheYawOnTheCircle) {
  FeetPose f = Stance(0.2);
  f.yaw[kLeft] = M_PI - 0.1;
  f.yaw[kRight] = -M_PI + 0.1;
  EXPECT_NEAR(std::cos(MidFrame(f).yaw), -1, 1e-12);
  EXPECT_NEAR(MidFrame(f).p.norm(), 0, 1e-12);
}

}  // namespace
}  // namespace ohrp::walking
