// Tests of the swing's travel onto a slope (Gait::Travel): a height change that the landing
// surface's tilt explains over the travel is no stair edge, so the foot goes forward after the
// short vertical share (GaitOptions::vertical_fraction) instead of the stairs' long one; the same
// rise onto a level surface is a stair and keeps the long vertical share.
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

}  // namespace
}  // namespace ohrp::walking
