// Tests of the swing's detour (robot_model/src/walking/gait.cc, Gait::SwingDetour): along the
// whole swing of random footsteps within the limits, the swinging sole keeps the clearance to the
// stance sole (or what the ends of its path have, if less); a straight path does not.
#include <gtest/gtest.h>

#include <algorithm>

#include "stances.h"
#include "walking/footsteps.h"
#include "walking/gait.h"

namespace ohrp::walking {
namespace {

// the least of (gap along the swing) - (the gap it must keep), over every step of `steps`
// sampled every 5 ms, and how many steps bent their path
struct SwingGaps {
  double worst = 1e9;  // [m]
  int bent = 0;
};
SwingGaps Walk(const FeetPose& start, const std::vector<Footstep>& steps, const StepLimits& l,
               const GaitOptions& o) {
  Gait g;
  g.Start(0, start, o);
  g.Replace(0, steps);
  SwingGaps r;
  for (int k = 0; k < g.step_count(); ++k) {
    const FeetPose before = g.FeetAfter(k - 1);
    const Footstep& s = g.step(k);
    const int st = 1 - s.foot;
    const double at_ends = std::min(SoleGap(before.p[s.foot], before.yaw[s.foot], before.p[st], before.yaw[st], l),
                                    SoleGap(s.p, s.yaw, before.p[st], before.yaw[st], l));
    const double need = std::min(l.clearance, at_ends);
    double least = 1e9;
    for (double t = g.step_lift(k); t <= g.step_land(k); t += 0.005) {
      GaitState state;
      g.At(t, &state);
      least = std::min(least, SoleGap(state.feet.p[s.foot], state.feet.yaw[s.foot], state.feet.p[st],
                                      state.feet.yaw[st], l));
    }
    r.worst = std::min(r.worst, least - need);
    GaitState mid;
    g.At(0.5 * (g.step_lift(k) + g.step_land(k)), &mid);
    const Eigen::Vector3d straight = 0.5 * (before.p[s.foot] + s.p);
    if ((mid.feet.p[s.foot] - straight).head<2>().norm() > 1e-6) ++r.bent;
  }
  return r;
}

TEST(SwingDetour, TheSwingingSoleKeepsTheClearanceAlongItsPath) {
  StepLimits l;  // HRP-1S's soles and width
  l.width = 0.18;
  l.sole_half_size = Eigen::Vector2d(0.125, 0.07);
  GaitOptions o;
  o.sole_half_length = l.sole_half_size.x();
  o.sole_half_width = l.sole_half_size.y();
  o.swing_clearance = l.clearance;
  GaitOptions straight = o;
  straight.sole_half_width = 0;  // the sole's size unknown: straight paths
  const FeetPose start = Stance(l.width);
  double worst_bent = 1e9, worst_straight = 1e9;
  int bent = 0;
  for (unsigned seed = 1; seed <= 10; ++seed) {
    const auto steps = PlanRandom(start, 40, seed, l);
    ASSERT_FALSE(steps.empty());
    const SwingGaps a = Walk(start, steps, l, o), b = Walk(start, steps, l, straight);
    worst_bent = std::min(worst_bent, a.worst);
    worst_straight = std::min(worst_straight, b.worst);
    bent += a.bent;
    EXPECT_EQ(b.bent, 0);
  }
  // the path is checked at 9 points: between them, a few mm at most
  EXPECT_GT(worst_bent, -0.003) << "straight: " << worst_straight;
  EXPECT_LT(worst_straight, -0.01);  // straight, some soles pass 1 cm closer than they must
  EXPECT_GT(bent, 0);
}

}  // namespace
}  // namespace ohrp::walking
