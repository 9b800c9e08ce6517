// Tests of the footstep limits (robot_model/src/walking/footsteps.cc): each limit of CheckStep
// passes a step on it and refuses one beyond it, naming the limit; the sole gap against closed
// forms; the mid frame.
#include "walking/footsteps.h"

#include <gtest/gtest.h>

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

TEST(MidFrame, AveragesTheYawOnTheCircle) {
  FeetPose f = Stance(0.2);
  f.yaw[kLeft] = M_PI - 0.1;
  f.yaw[kRight] = -M_PI + 0.1;
  EXPECT_NEAR(std::cos(MidFrame(f).yaw), -1, 1e-12);
  EXPECT_NEAR(MidFrame(f).p.norm(), 0, 1e-12);
}

}  // namespace
}  // namespace ohrp::walking
