// Tests of a step up onto a stair (Gait::Replace, Gait::At): the ground under the CoM rises over
// the step as far as the trailing leg still reaches (StepUpRise, its closed form), the rest with
// the next step; the foot leaving the lower level rolls onto its toe (toes down about the toe,
// the toe never below where it stood, level again by half its travel). A rise that a slope's
// tilt explains is no stair: no early rise, no toe roll. A stride over a stair onto the next (one
// foot per stair) rises above the stair it passes before it travels (Footstep::lift_z), one past
// a stair down comes down above it before it lands (land_z).
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
  // then level again with the travel: at 0.6 of the swing (the travel from 0.3 to 0.7)
  double f, df, ddf;
  MinJerk((0.6 - 0.3) / 0.4, &f, &df, &ddf);
  g.At(lift + 0.6 * (land - lift), &st);
  EXPECT_NEAR(st.feet.pitch[kRight], most_allowed * (1 - f), 1e-9);
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

// a stride over a stair onto the next (one foot per stair): the right foot from the floor 0.6 m
// ahead onto a tread 0.3 m up, over one 0.15 m up (Footstep::lift_z). The swing rises to the
// apex above that first stair before it travels and on to the apex above the landing with the
// travel's first half; without lift_z it rises to the top behind, as before
TEST(StairStride, TheSwingRisesAboveTheStairItPassesThenOnWithItsTravel) {
  const GaitOptions o = StairOptions();
  for (double lift_z : {0.15, -1e9}) {
    Gait g = StepOnto(o, 0.0, 0);
    Footstep s;
    s.foot = kRight;
    s.p = Eigen::Vector3d(0.6, -0.09, 0.30);
    s.clear_z = 0.15;
    s.lift_z = lift_z;
    g.Replace(0, {s});
    const double top = 0.30 + o.step_height, lift = lift_z > 0 ? lift_z + o.step_height : top;
    const double t0 = g.step_lift(0), T = g.step_land(0) - t0;
    GaitState st;
    for (double ph = 0; ph < 0.5; ph += 0.01) {
      g.At(t0 + ph * T, &st);
      double f, df, ddf, ft, dft, ddft, h, dh, ddh;
      MinJerk(ph / 0.5, &f, &df, &ddf);
      MinJerk((ph - 0.3) / 0.4, &ft, &dft, &ddft);  // the travel: vertical 0.3 at each end
      MinJerk(std::min(2 * ft, 1.0), &h, &dh, &ddh);
      // the toe-off raises the sole's centre by half sin(pitch) about the toe
      const double toe_z = st.feet.p[kRight].z() - o.sole_half_length * std::sin(st.feet.pitch[kRight]);
      EXPECT_NEAR(toe_z, f * lift + h * (top - lift), 1e-9) << ph << " " << lift_z;
      if (ph <= 0.3) {
        EXPECT_LE(toe_z, lift + 1e-9) << ph;  // behind the hip: no higher than that
      }
    }
    g.At(t0 + 0.5 * T, &st);
    EXPECT_NEAR(st.feet.p[kRight].z() - o.sole_half_length * std::sin(st.feet.pitch[kRight]), top, 1e-9);
  }
}

// a stride past a stair onto the one below: the right foot from a platform 0.6 m ahead onto a
// tread 0.3 m down, past one 0.15 m down (Footstep::land_z): over the travel's second half the
// swing comes down from the apex above the platform to the apex above the stair it passes, then
// lands vertically from there; without land_z it stays at the top until its landing share
TEST(StairStride, OffAStairTheSwingComesDownAboveTheStairItPasses) {
  const GaitOptions o = StairOptions();
  for (double land_z : {-0.15, -1e9}) {
    Gait g = StepOnto(o, 0.0, 0);
    Footstep s;
    s.foot = kRight;
    s.p = Eigen::Vector3d(0.6, -0.09, -0.30);
    s.land_z = land_z;
    g.Replace(0, {s});
    const double top = o.step_height, land = land_z > -1 ? land_z + o.step_height : top;
    const double t0 = g.step_lift(0), T = g.step_land(0) - t0;
    GaitState st;
    // off a stair the travel runs from 0.05 (the short vertical share) to 0.7 of the swing
    for (double ph = 0.5; ph <= 0.7; ph += 0.01) {
      g.At(t0 + ph * T, &st);
      double ft, dft, ddft, h, dh, ddh;
      MinJerk((ph - 0.05) / 0.65, &ft, &dft, &ddft);
      MinJerk(std::max(2 * ft - 1, 0.0), &h, &dh, &ddh);
      EXPECT_NEAR(st.feet.p[kRight].z(), top - h * (top - land), 1e-9) << ph << " " << land_z;
    }
    for (double ph = 0.7; ph <= 1.0; ph += 0.01) {
      g.At(t0 + ph * T, &st);
      double f, df, ddf;
      MinJerk((ph - 0.7) / 0.3, &f, &df, &ddf);
      EXPECT_NEAR(st.feet.p[kRight].z(), land + f * (-0.30 - land), 1e-9) << ph << " " << land_z;
    }
  }
}

}  // namespace
}  // namespace ohrp::walking
