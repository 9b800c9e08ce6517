// Tests of a landing moved during the swing (Gait::AdjustLanding, the walk's stepping strategy):
// the swing foot's path stays continuous, lands at the new place, and the later steps' stance
// and the ZMP reference follow it; outside the single support nothing moves. A landing held for a
// late touchdown (Gait::DelayLanding): the swing continuous, the landing and every later step
// later by the delay, the ZMP on the stance sole until then.
#include <gtest/gtest.h>

#include "stances.h"
#include "walking/footsteps.h"
#include "walking/gait.h"

namespace ohrp::walking {
namespace {

Footstep Step(int foot, double x, double y) {
  Footstep s;
  s.foot = foot;
  s.p = Eigen::Vector3d(x, y, 0);
  return s;
}

TEST(AdjustLanding, TheSwingGoesOnFromWhereItIsToTheNewLanding) {
  const double w = 0.18;
  Gait g;
  GaitOptions o;
  g.Start(0, Stance(w), o);
  g.Reserve(8);
  g.Replace(0, {Step(kLeft, 0.2, 0.09), Step(kRight, 0.4, -0.09), Step(kLeft, 0.4, 0.09)});
  const double lift = g.step_lift(0), land = g.step_land(0);
  const double now = lift + 0.4 * (land - lift);
  GaitState before, after;
  g.At(now, &before);
  ASSERT_EQ(before.swing, kLeft);
  const Eigen::Vector2d moved(0.25, 0.19);  // 5 cm ahead and 10 cm out
  ASSERT_TRUE(g.AdjustLanding(0, moved, now));
  g.At(now, &after);
  // continuous where it is now, and a little later close by
  EXPECT_NEAR((after.feet.p[kLeft] - before.feet.p[kLeft]).norm(), 0, 1e-12);
  GaitState next;
  g.At(now + 0.005, &next);
  EXPECT_LT((next.feet.p[kLeft] - after.feet.p[kLeft]).head<2>().norm(), 0.01);
  // it lands at the new place; the next step stands on it and its ZMP reference goes there
  GaitState landed;
  g.At(land, &landed);
  EXPECT_NEAR((landed.feet.p[kLeft].head<2>() - moved).norm(), 0, 1e-9);
  EXPECT_NEAR((g.FeetAfter(0).p[kLeft].head<2>() - moved).norm(), 0, 1e-9);
  GaitState single;
  g.At(0.5 * (g.step_lift(1) + g.step_land(1)), &single);  // the right foot swings, on the left
  EXPECT_NEAR((single.zmp.head<2>() - moved).norm(), 0, 1e-9);
  // the later steps keep their places
  EXPECT_NEAR((g.step(1).p - Eigen::Vector3d(0.4, -0.09, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((g.step(2).p - Eigen::Vector3d(0.4, 0.09, 0)).norm(), 0, 1e-12);
  EXPECT_EQ(g.step_count(), 3);
}

TEST(AdjustLanding, OutsideTheSingleSupportNothingMoves) {
  Gait g;
  GaitOptions o;
  g.Start(0, Stance(0.18), o);
  g.Reserve(8);
  g.Replace(0, {Step(kLeft, 0.2, 0.09), Step(kRight, 0.4, -0.09)});
  const Eigen::Vector2d moved(0.3, 0.2);
  EXPECT_FALSE(g.AdjustLanding(0, moved, g.step_begin(0)));          // in the double support
  EXPECT_FALSE(g.AdjustLanding(0, moved, g.step_land(0) + 0.01));    // landed
  EXPECT_FALSE(g.AdjustLanding(5, moved, g.step_lift(0) + 0.1));     // no such step
  EXPECT_NEAR((g.step(0).p - Eigen::Vector3d(0.2, 0.09, 0)).norm(), 0, 1e-12);
}

// a swing shortened (Gait::AdjustStep): the foot is where it was at that moment, lands at the
// new place at the new time, its phase goes on linearly from there to 1; the later steps follow
// at the default timing from the new landing, moved with it (carry_later)
TEST(AdjustStep, AShorterSwingLandsSoonerAndTheLaterStepsFollowTheFoothold) {
  Gait g;
  GaitOptions o;
  g.Start(0, Stance(0.18), o);
  g.Reserve(8);
  g.Replace(0, {Step(kLeft, 0.2, 0.09), Step(kRight, 0.4, -0.09), Step(kLeft, 0.6, 0.09)});
  const double lift = g.step_lift(0), land = g.step_land(0);
  const double now = lift + 0.4 * (land - lift);
  GaitState before, after;
  g.At(now, &before);
  const Eigen::Vector2d moved(0.2, 0.14);  // 5 cm out
  const double t_land = now + 0.5 * (land - now);
  EXPECT_FALSE(g.AdjustStep(0, moved, land + 0.01, true, now));  // later than planned: refused
  EXPECT_FALSE(g.AdjustStep(0, moved, now, true, now));          // not after now: refused
  ASSERT_TRUE(g.AdjustStep(0, moved, t_land, true, now));
  g.At(now, &after);
  EXPECT_NEAR((after.feet.p[kLeft] - before.feet.p[kLeft]).norm(), 0, 1e-12);
  EXPECT_NEAR(after.swing_phase, 0.4, 1e-12);
  GaitState mid;
  g.At(0.5 * (now + t_land), &mid);
  EXPECT_NEAR(mid.swing_phase, 0.7, 1e-12);  // halfway from 0.4 to 1
  EXPECT_DOUBLE_EQ(g.step_land(0), t_land);
  GaitState landed;
  g.At(t_land, &landed);
  EXPECT_EQ(landed.swing, -1);
  EXPECT_NEAR((landed.feet.p[kLeft].head<2>() - moved).norm(), 0, 1e-9);
  // the next step begins at the new landing with the default timing
  EXPECT_DOUBLE_EQ(g.step_begin(1), t_land);
  EXPECT_NEAR(g.step_lift(1) - g.step_begin(1), o.double_support_ratio * o.step_time, 1e-12);
  EXPECT_NEAR(g.step_land(1) - g.step_begin(1), o.step_time, 1e-12);
  // and the later steps moved by the landing's change (0, +0.05)
  EXPECT_NEAR((g.step(1).p - Eigen::Vector3d(0.4, -0.04, 0)).norm(), 0, 1e-12);
  EXPECT_NEAR((g.step(2).p - Eigen::Vector3d(0.6, 0.14, 0)).norm(), 0, 1e-12);
}

TEST(DelayLanding, TheLandingAndTheLaterStepsWaitTheZmpStaysOnTheStance) {
  const double w = 0.18;
  Gait g;
  GaitOptions o;
  g.Start(0, Stance(w), o);
  g.Reserve(8);
  g.Replace(0, {Step(kLeft, 0.2, 0.09), Step(kRight, 0.4, -0.09), Step(kLeft, 0.4, 0.09)});
  const double lift = g.step_lift(0), land = g.step_land(0);
  const double later_begin = g.step_begin(1), later_land = g.step_land(1), end = g.end_time();
  const double now = land - 0.005, delay = 0.2;
  GaitState before, after;
  g.At(now, &before);
  ASSERT_TRUE(g.DelayLanding(0, delay, now));
  g.At(now, &after);
  EXPECT_NEAR((after.feet.p[kLeft] - before.feet.p[kLeft]).norm(), 0, 1e-12);  // continuous
  EXPECT_NEAR(g.step_land(0), land + delay, 1e-12);
  EXPECT_NEAR(g.step_begin(1), later_begin + delay, 1e-12);
  EXPECT_NEAR(g.step_land(1), later_land + delay, 1e-12);
  EXPECT_NEAR(g.end_time(), end + delay, 1e-12);
  // still in single support on the right sole at the old landing, the ZMP on it
  GaitState held;
  g.At(land + 0.5 * delay, &held);
  EXPECT_EQ(held.swing, kLeft);
  EXPECT_NEAR((held.zmp.head<2>() - Stance(w).p[kRight].head<2>()).norm(), 0, 1e-9);
  // the foot reaches its landing at the new time
  GaitState landed;
  g.At(land + delay - 1e-9, &landed);
  EXPECT_NEAR((landed.feet.p[kLeft] - Eigen::Vector3d(0.2, 0.09, 0)).norm(), 0, 1e-6);
  // nothing outside the single support, nor without a delay
  EXPECT_FALSE(g.DelayLanding(0, delay, lift - 0.01));
  EXPECT_FALSE(g.DelayLanding(0, 0.0, now));
  EXPECT_FALSE(g.DelayLanding(5, delay, now));
}

}  // namespace
}  // namespace ohrp::walking
