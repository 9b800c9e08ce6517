// Tests of a step up onto a stair (Gait::Replace, Gait::At): the ground under the CoM rises over
// the step as far as the trailing leg still reaches (StepUpRise, its closed form), the rest with
// the next step; the foot leaving the lower level rolls onto its toe (toes down about the toe,
// the toe never below where it stood, level again by half its travel). A rise that a slope's
// tilt explains is no stair: no early rise, no toe roll.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "stances.h"
#include "walking/footsteps.h"
#include "walking/gait.h"

namespace ohrp::walking {
namespace {

GaitOptions StairOptions() {
  GaitOptions o;
  o.leg_reach = 0.70;
  o.hip_height = 0.64;
  o.sole_half_length = 0.125;
  o.step_height = 0.05;
  return o;
}

TEST(StepUp, TheCoMRisesAsFarAsTheTrailingLegReaches) {
  GaitOptions o = StairOptions();
  const double height = 0.15, reach_xy = 0.30;
  const double rise = StepUpRise(o, height, reach_xy);
  EXPECT_NEAR(rise, std::sqrt(0.70 * 0.70 - 0.15 * 0.15) - 0.64, 1e-12);
  // the trailing leg's hip, half the step ahead of its sole, at the reach exactly
  EXPECT_NEAR(std::hypot(o.hip_height + rise, reach_xy / 2), o.leg_reach, 1e-12);
  EXPECT_EQ(StepUpRise(o, -0.15, reach_xy), 0.0);      // down
  EXPECT_EQ(StepUpRise(o, 0.0, reach_xy), 0.0);        // flat
  EXPECT_NEAR(StepUpRise(o, 0.01, 0.1), 0.01, 1e-12);  // never more than the step's height
  EXPECT_EQ(StepUpRise(o, height, 1.0), 0.0);          // a stride the leg barely reaches: none
  o.leg_reach = 0;                                     // reach unknown: no rise
  EXPECT_EQ(StepUpRise(o, height, reach_xy), 0.0);
}

// the right foot 0.3 m ahead onto a stair `height` up with the given surface pitch
Gait StepOnto(const GaitOptions& o, double height, double pitch) {
  Gait g;
  g.Start(0, Stance(0.18), o);
  g.Reserve(4);
  Footstep s;
  s.foot = kRight;
  s.p = Eigen::Vector3d(0.3, -0.09, height);
  s.pitch = pitch;
  g.Replace(0, {s});
  return g;
}

// a swing over terrain higher than both its ends (Footstep::clear_z, from the scene): its apex
// is `height` above that terrain, reached at mid-swing; without it, above the higher end
TEST(StepUp, TheSwingApexIsAboveTheHighestTerrainOnItsWay) {
  const GaitOptions o = StairOptions();
  for (double clear : {0.1, -1e9}) {
    Gait g = StepOnto(o, 0.0, 0);
    Footstep s;
    s.foot = kRight;
    s.p = Eigen::Vector3d(0.3, -0.09, 0);
    s.clear_z = clear;
    g.Replace(0, {s});
    double top = -1;
    GaitState st;
    for (double t = g.step_lift(0); t <= g.step_land(0); t += 1e-3) {
      g.At(t, &st);
      top = std::max(top, st.feet.p[kRight].z());
    }
    EXPECT_NEAR(top, std::max(clear, 0.0) + o.step_height, 1e-6) << clear;
  }
}

TEST(StepUp, TheGroundRisesOverTheStepOntoTheStair) {
  const GaitOptions o = StairOptions();
  const double height = 0.15;
  Gait g = StepOnto(o, height, 0);
  GaitState st;
  g.At(g.step_land(0) - 1e-9, &st);
  // the stance (left) sole at 0, the landing sole 0.3 ahead and 0.09 + 0.09 aside
  EXPECT_NEAR(st.zmp.z(), StepUpRise(o, height, std::hypot(0.3, 0.18)), 1e-6);
  // a slope: the same rise over a surface tilted as much is no stair edge, no early rise
  Gait s = StepOnto(o, height, std::atan2(height, 0.3));
  s.At(s.step_land(0) - 1e-9, &st);
  EXPECT_NEAR(st.zmp.z(), 0.0, 1e-9);
}

TEST(StepUp, TheTrailingFootRollsOntoItsToe) {
  const GaitOptions o = StairOptions();
  Gait g = StepOnto(o, 0.15, 0);
  const double lift = g.step_lift(0), land = g.step_land(0);
  const double most_allowed = 0.8 * std::asin(o.step_height / o.sole_half_length);
  const double toe0_x = 0.0 + o.sole_half_length;  // where the toe stood
  GaitState st;
  double most = 0;
  for (double ph = 0; ph <= 1.0 + 1e-9; ph += 0.01) {
    g.At(lift + ph * (land - lift), &st);
    const double a = st.feet.pitch[kRight];
    most = std::max(most, a);
    EXPECT_GE(a, -1e-12) << ph;
    EXPECT_LE(a, most_allowed + 1e-12) << ph;
    // the toe (sole centre + half length along the pitched sole) never below the floor it left
    const double toe_z = st.feet.p[kRight].z() - o.sole_half_length * std::sin(a);
    EXPECT_GE(toe_z, -1e-9) << ph;
    // over the vertical lift (0.3 of the swing onto a stair), the toe stays where it stood (a
    // roll about the toe)
    if (ph < 0.3 - 1e-9) {
      const double toe_x = st.feet.p[kRight].x() + o.sole_half_length * std::cos(a);
      EXPECT_NEAR(toe_x, toe0_x, 1e-9) << ph;
    }
  }
  EXPECT_NEAR(most, most_allowed, 1e-9);  // reached (full over most of the lift)
  g.At(lift + 0.6 * (land - lift), &st);  // past half the travel: level
  EXPECT_NEAR(st.feet.pitch[kRight], 0.0, 1e-12);
  g.At(land - 1e-9, &st);
  EXPECT_NEAR(st.feet.pitch[kRight], 0.0, 1e-12);
  EXPECT_NEAR(st.feet.p[kRight].z(), 0.15, 1e-6);
  // the same height up a slope: no roll, the pitch goes with the travel alone
  const double slope = std::atan2(0.15, 0.3);
  Gait s = StepOnto(o, 0.15, slope);
  for (double ph : {0.02, 0.1, 0.3}) {
    s.At(s.step_lift(0) + ph * (s.step_land(0) - s.step_lift(0)), &st);
    EXPECT_NEAR(st.feet.pitch[kRight], st.feet.p[kRight].x() / 0.3 * slope, 1e-12) << ph;
  }
}

}  // namespace
}  // namespace ohrp::walking
