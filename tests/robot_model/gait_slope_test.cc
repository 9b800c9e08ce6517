// Tests of the swing's travel onto and down a slope (Gait::Travel, Gait::At): a height change that
// the surfaces' tilt explains over the travel is no stair edge, so the foot goes forward after the
// short vertical share (GaitOptions::vertical_fraction) instead of the stairs' long one, and a
// drop down a slope comes down from mid-swing (no stair to leave); the same rise or drop onto a
// level surface is a stair.
#include <gtest/gtest.h>

#include <cmath>

#include "stances.h"
#include "walking/footsteps.h"
#include "walking/gait.h"

namespace ohrp::walking {
namespace {

// x of the left swing foot at `phase` of its single support, stepping 0.2 m forward and
// 0.2 tan(7 deg) up onto a surface pitched by `pitch`
double SwingX(double pitch, double phase) {
  Gait g;
  GaitOptions o;
  g.Start(0, Stance(0.18), o);
  g.Reserve(4);
  Footstep s;
  s.foot = kLeft;
  s.p = Eigen::Vector3d(0.2, 0.09, 0.2 * std::tan(7 * M_PI / 180));
  s.pitch = pitch;
  g.Replace(0, {s});
  const double lift = g.step_lift(0), land = g.step_land(0);
  GaitState st;
  g.At(lift + phase * (land - lift), &st);
  return st.feet.p[kLeft].x();
}

double MinJerk(double s) { return s * s * s * (10 - 15 * s + 6 * s * s); }

TEST(SwingOntoSlope, ARiseTheSlopeExplainsLeavesAfterTheShortVerticalShare) {
  const double vf = GaitOptions().vertical_fraction;
  const double phase = 0.2;
  // closed form: minimum jerk over [vf, 1 - vf] of the single support
  const double expected = 0.2 * MinJerk((phase - vf) / (1 - 2 * vf));
  EXPECT_NEAR(SwingX(-7 * M_PI / 180, phase), expected, 1e-9);
  EXPECT_GT(expected, 0.005);
}

TEST(SwingOntoSlope, TheSameRiseOntoALevelSurfaceIsAStairAndWaits) {
  EXPECT_NEAR(SwingX(0, 0.2), 0, 1e-12);  // still rising vertically at 0.2 (share 0.3)
}

// the left swing foot at `phase` of its single support, stepping `run` forward and down by
// run tan(7 deg) from a surface pitched by `pitch_from` onto one pitched by `pitch_to`
GaitState SwingDown(double run, double pitch_from, double pitch_to, double phase) {
  Gait g;
  GaitOptions o;
  FeetPose start = Stance(0.18);
  start.pitch[kLeft] = pitch_from;
  g.Start(0, start, o);
  g.Reserve(4);
  Footstep s;
  s.foot = kLeft;
  s.p = Eigen::Vector3d(run, 0.09, -run * std::tan(7 * M_PI / 180));
  s.pitch = pitch_to;
  g.Replace(0, {s});
  const double lift = g.step_lift(0), land = g.step_land(0);
  GaitState st;
  g.At(lift + phase * (land - lift), &st);
  return st;
}

constexpr double kDown7 = 7 * M_PI / 180;  // a surface falling forward: toes down, pitch > 0

TEST(SwingDownSlope, ADropDeeperThanTheApexThatTheSlopeExplainsComesDownOverHalfTheSwing) {
  // 0.48 m down a 7 deg slope drops 59 mm, more than the 40 mm apex: still no stair to leave, so
  // the foot comes down from the apex from mid-swing (minimum jerk over [0.5, 1]), not at the end
  const GaitOptions o;
  const double run = 0.48, drop = run * std::tan(kDown7);
  ASSERT_GT(drop, o.step_height);
  const double phase = 0.75;
  const double top = o.step_height;  // above the higher end, the lift-off sole at z = 0
  const double expected = top + MinJerk((phase - 0.5) / 0.5) * (-drop - top);
  const GaitState st = SwingDown(run, kDown7, kDown7, phase);
  EXPECT_NEAR(st.feet.p[kLeft].z(), expected, 1e-9);
  // and no heel lift: the sole keeps the slope's pitch
  EXPECT_NEAR(st.feet.pitch[kLeft], kDown7, 1e-9);
}

TEST(SwingDownSlope, TheSameDropOffALevelStairWaitsAtTheTop) {
  // level soles: the drop is a stair's edge, the foot stays at the apex past mid-swing (until
  // the stairs' landing share, 0.3 of the single support, is left)
  const GaitOptions o;
  const GaitState st = SwingDown(0.48, 0, 0, 0.65);
  EXPECT_NEAR(st.feet.p[kLeft].z(), o.step_height, 1e-9);
}

}  // namespace
}  // namespace ohrp::walking
