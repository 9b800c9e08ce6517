// Tests the gait's start_rock and stop_rock (gait.h) against closed forms: the first step from
// standing holds the ZMP on the swinging sole for half a single support, then puts it on the
// stance sole; and the preview's CoM then sways sideways by about the linear inverted
// pendulum's periodic orbit d (1 - 1 / cosh(omega T_single / 2)) from the first step to the
// stop, where a start from the feet's middle and a stop over end_time make transients several
// times larger (legs without an ankle roll: docs/robots.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "walking/gait.h"
#include "walking/pattern_generator.h"

namespace ohrp::walking {
namespace {

FeetPose Stance(double half_width) {
  FeetPose f;
  f.p[kLeft] = Eigen::Vector3d(0, half_width, 0);
  f.p[kRight] = Eigen::Vector3d(0, -half_width, 0);
  f.yaw[0] = f.yaw[1] = 0;
  return f;
}

// n steps in place, the left foot first
std::vector<Footstep> InPlace(int n, double half_width) {
  std::vector<Footstep> steps;
  for (int k = 0; k < n; ++k) {
    Footstep s;
    s.foot = k % 2 == 0 ? kLeft : kRight;
    s.p = Eigen::Vector3d(0, s.foot == kLeft ? half_width : -half_width, 0);
    steps.push_back(s);
  }
  return steps;
}

TEST(Gait, StartRockHoldsTheZmpOnTheSwingingSoleForHalfASingleSupport) {
  GaitOptions o;
  o.start_rock = true;
  o.step_time = 0.32;
  o.double_support_ratio = 0.05;
  const double d = 0.2;
  const FeetPose feet = Stance(d);
  Gait g;
  g.Start(0, feet, o);
  g.Replace(0, InPlace(1, d));
  const double t0 = o.start_delay;
  const double single = (1 - o.double_support_ratio) * o.step_time;
  const double t_lift = t0 + 0.5 * single;  // start_time is not used
  GaitState st;
  g.At(t0 - 1e-3, &st);  // standing: the middle
  EXPECT_LT(st.zmp.head<2>().norm(), 1e-9);
  for (double t : {t0 + 1e-9, 0.5 * (t0 + t_lift), t_lift - 1e-6}) {
    g.At(t, &st);
    EXPECT_LT((st.zmp.head<2>() - feet.p[kLeft].head<2>()).norm(), 1e-9) << t;
    EXPECT_EQ(st.swing, -1) << t;  // both feet still down
  }
  g.At(t_lift + 1e-6, &st);
  EXPECT_LT((st.zmp.head<2>() - feet.p[kRight].head<2>()).norm(), 1e-9);
  EXPECT_EQ(st.swing, kLeft);
  g.At(t_lift + single - 1e-6, &st);  // the single support is the whole one
  EXPECT_EQ(st.swing, kLeft);
  g.At(t_lift + single + 1e-6, &st);
  EXPECT_EQ(st.swing, -1);
}

// the largest sideways excursion of the planned CoM from the middle over a walk in place, while
// the preview does not see the stop yet (`*stop`: from then on: the final double support, which
// moves the ZMP back to the middle over end_time, is in its horizon)
double PlannedSway(bool rock, double d, double zc, const GaitOptions& base, double* stop) {
  GaitOptions o = base;
  o.start_rock = o.stop_rock = rock;
  PreviewOptions p;
  p.dt = 0.004;
  p.zc = zc;
  PatternGenerator g;
  std::string error;
  EXPECT_TRUE(g.Configure(o, p, &error)) << error;
  EXPECT_TRUE(g.Start(0, Stance(d), Eigen::Vector3d(0, 0, zc), &error)) << error;
  g.Replace(InPlace(20, d));
  const double t_last = g.gait().end_time() - g.gait().StopHold() - o.end_time - p.preview_time;
  double sway = 0;
  *stop = 0;
  while (g.walking()) {
    const WalkSample& w = g.Advance();
    double& m = w.t <= t_last ? sway : *stop;
    m = std::max(m, std::abs(w.com.y()));
  }
  return sway;
}

// H1's figures (docs/robots.md): soles 0.2 m either side, the CoM 0.93 m up, 0.32 s steps with
// 5 % double support. The preview's CoM is the cart-table's for a ZMP that tracks the
// reference, whose periodic orbit for a ZMP jumping between +-d is the LIPM's; the preview moves
// the CoM before the first step (its anticipation) and the double support's ramp shortens the
// jumps: within 30 % of the orbit's sway with start_rock, and the start from the middle at least
// twice the orbit's (the transient the option removes)
TEST(Gait, StartAndStopRockSwayByTheLipmPeriodicOrbit) {
  const double d = 0.2, zc = 0.93, g = 9.81;
  GaitOptions o;
  o.step_time = 0.32;
  o.double_support_ratio = 0.05;
  o.start_time = 0.2;
  o.end_time = 0.8;
  const double omega = std::sqrt(g / zc);
  const double single = (1 - o.double_support_ratio) * o.step_time;
  const double orbit = d * (1 - 1 / std::cosh(omega * single / 2));
  double stop_rock = 0, stop_middle = 0;
  const double rock = PlannedSway(true, d, zc, o, &stop_rock);
  const double middle = PlannedSway(false, d, zc, o, &stop_middle);
  EXPECT_LT(rock, 1.3 * orbit) << "orbit " << orbit;
  EXPECT_GT(middle, 2.0 * orbit) << "orbit " << orbit;
  // the stop (stop_rock): within 50 % of the orbit's (the preview sees the hold and the jump to
  // the middle a horizon ahead), the stop from the last sole over end_time at least twice it
  EXPECT_LT(stop_rock, 1.5 * orbit) << "orbit " << orbit;
  EXPECT_GT(stop_middle, 2.0 * orbit) << "orbit " << orbit;
}

}  // namespace
}  // namespace ohrp::walking
