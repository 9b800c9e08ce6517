// Tests the balance controller closed-loop on the simulated HRP-1S (in-process, soft soles,
// 1 ms physics, 5 ms control; tests/controllers/balance_trials.h), judged on the simulation's
// truth: it settles after pushes in 8 directions (the issue's targets: base back within 1 cm
// and the ankle torque oscillation below 10 % of its first peak within 1 s), its base estimate
// stays within the issue's bounds while pushed, it stands on one leg on each side on the flat
// and on the wavy floor, and it stands with both soles flat on the wavy floor and on the ramp.
// The cross-process versions (sim_host + balance, ./ohrp push) run in tests/integration.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

#include "balance_trials.h"

namespace ohrp::controllers::testing {
namespace {

constexpr double kDeg = M_PI / 180;

class BalancePushed : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override { model::InstallMujocoHandlers(nullptr); }
};

TEST_P(BalancePushed, SettlesWithinOneSecondAfter15Ns) {
  Trial t;
  t.direction = GetParam();
  t.impulse = 15.0;
  const PushOutcome r = RunPushTrial(t);
  ASSERT_TRUE(r.standing);
  EXPECT_GE(r.base_settle, 0.0);
  EXPECT_LE(r.base_settle, 1.0);
  EXPECT_GE(r.torque_settle, 0.0);
  EXPECT_LE(r.torque_settle, 1.0) << "first peak " << r.torque_peak << " N m";
  EXPECT_EQ(r.nonfinite_commands, 0u);
  std::printf("balance, 15 N s at %3d deg: base settles %.3f s, ankle torques %.3f s (peak %.1f N m)\n",
              GetParam(), r.base_settle, r.torque_settle, r.torque_peak);
}

TEST_P(BalancePushed, EstimatorStaysWithinTheIssuesBoundsWhilePushed) {
  // tilt < 0.5 deg and base height < 5 mm (changes since the stance: the estimate's origin is
  // the soles' plane, the truth's the floor)
  Trial t;
  t.direction = GetParam();
  t.impulse = 40.0;
  const PushOutcome r = RunPushTrial(t);
  ASSERT_TRUE(r.standing);
  EXPECT_LT(r.estimator_tilt_error, 0.5 * kDeg);
  EXPECT_LT(r.estimator_height_error, 0.005);
  std::printf("balance, 40 N s at %3d deg: estimator tilt error %.3f deg, height error %.2f mm\n",
              GetParam(), r.estimator_tilt_error / kDeg, r.estimator_height_error * 1e3);
}

INSTANTIATE_TEST_SUITE_P(EightDirections, BalancePushed,
                         ::testing::Values(0, 45, 90, 135, 180, 225, 270, 315));

// one leg: the CoM over one sole, the other 5 cm up for 5 s, down, on each side
void ExpectOneLeg(const std::string& scene, const std::string& keyframe) {
  model::InstallMujocoHandlers(nullptr);
  Trial t;
  t.scene = scene;
  t.keyframe = keyframe;
  t.options.one_leg.sides = {0, 1};
  const OneLegOutcome r = RunOneLegTrial(t);
  ASSERT_TRUE(r.standing);
  EXPECT_EQ(r.holds, 2);
  // fully lifted: the hold, plus the ends of the minimum-jerk lift and lowering above 99.9 %
  EXPECT_GE(r.hold_time, 2 * t.options.one_leg.hold);
  EXPECT_LE(r.hold_time, 2 * t.options.one_leg.hold + 0.4);
  EXPECT_GE(r.min_cop_margin, 0.01);           // the stance sole stays flat under its CoP
  EXPECT_LT(r.max_swing_fz, 5.0);              // the swing foot is in the air
  EXPECT_GE(r.min_lift, 0.95 * t.options.one_leg.lift);  // 5 cm, within 2.5 mm
  std::printf("one leg on %s: stance CoP at least %.1f mm inside, swing load at most %.1f N, "
              "lift at least %.1f mm\n",
              scene.c_str(), r.min_cop_margin * 1e3, r.max_swing_fz, r.min_lift * 1e3);
}

TEST(BalanceOneLeg, StandsOnEachLegOnTheFlatFloor) {
  ExpectOneLeg("mjcf/hrp1s/scene_flat.xml", "halfsit");
}

TEST(BalanceOneLeg, StandsOnEachLegOnTheWavyFloor) {
  ExpectOneLeg("mjcf/hrp1s/scene_uneven.xml", "halfsit_uneven");
}

// both soles flat: each sole's CoP at least 1 cm inside its edges, from 3 s to 8 s
void ExpectFlatSoles(const std::string& scene, const std::string& keyframe) {
  model::InstallMujocoHandlers(nullptr);
  Trial t;
  t.scene = scene;
  t.keyframe = keyframe;
  const StandOutcome r = RunStandTrial(t, 3.0, 8.0);
  ASSERT_TRUE(r.standing);
  for (int i = 0; i < 2; ++i) {
    EXPECT_GT(r.min_fz[i], kLoaded) << "sole " << i << " lifted";
    EXPECT_GE(r.min_cop_margin[i], 0.01) << "sole " << i << " stands on an edge";
  }
  std::printf("balance on %s: CoP at least %.1f mm (left) and %.1f mm (right) inside the soles\n",
              scene.c_str(), r.min_cop_margin[0] * 1e3, r.min_cop_margin[1] * 1e3);
}

TEST(BalanceStand, BothSolesFlatOnTheWavyFloor) {
  ExpectFlatSoles("mjcf/hrp1s/scene_uneven.xml", "halfsit_uneven");
}

TEST(BalanceStand, BothSolesFlatOnTheFiveDegreeRamp) {
  ExpectFlatSoles("mjcf/hrp1s/scene_slope.xml", "halfsit_ramp");
}

//---------------- a development aid (disabled) ----------------

double Env(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v ? std::atof(v) : fallback;
}

// settling, survival (OHRP_TUNE_BISECT) or one leg (OHRP_TUNE_ONELEG) for the gains in
// OHRP_TUNE_* variables
TEST(BalancePush, DISABLED_Explore) {
  model::InstallMujocoHandlers(nullptr);
  BalanceOptions o;
  StabilizerGains& g = o.gains;
  g.k_dcm = Env("OHRP_TUNE_KDCM", g.k_dcm);
  g.ankle_damping = Env("OHRP_TUNE_D", g.ankle_damping);
  g.ankle_recovery = Env("OHRP_TUNE_T", g.ankle_recovery);
  g.z_damping = Env("OHRP_TUNE_DZ", g.z_damping);
  g.hip_gain = Env("OHRP_TUNE_HIP", g.hip_gain);
  g.hip_return = Env("OHRP_TUNE_HIPW", g.hip_return);
  g.ankle_strategy = Env("OHRP_TUNE_ANKLE", 1) > 0;
  g.support_margin = Env("OHRP_TUNE_MARGIN", g.support_margin);
  g.ground_adaptation = Env("OHRP_TUNE_GA", g.ground_adaptation);
  o.centre_com = Env("OHRP_TUNE_CENTRE", 1) > 0;
  const double impulse = Env("OHRP_TUNE_IMPULSE", 15);
  const bool posture = Env("OHRP_TUNE_POSTURE", 0) > 0;
  if (Env("OHRP_TUNE_ONELEG", 0) > 0) {
    Trial t;
    t.options = o;
    t.options.one_leg.sides = {0, 1};
    if (const char* scene = std::getenv("OHRP_TUNE_SCENE")) t.scene = scene;
    if (const char* key = std::getenv("OHRP_TUNE_KEY")) t.keyframe = key;
    const OneLegOutcome r = RunOneLegTrial(t);
    std::printf("one leg: %s, min stance CoP margin %.1f mm, max swing load %.1f N, min lift %.1f mm\n",
                r.standing ? "standing" : "FELL", r.min_cop_margin * 1e3, r.max_swing_fz,
                r.min_lift * 1e3);
    return;
  }
  for (int dir = 0; dir < 360; dir += 45) {
    Trial t;
    t.balance = !posture;
    t.direction = dir;
    t.options = o;
    if (Env("OHRP_TUNE_BISECT", 0) > 0) {
      double found[2];
      for (int k = 0; k < 2; ++k) {
        t.balance = k == 0;
        double a = 0, b = 200;
        while (b - a > 2) {
          t.impulse = 0.5 * (a + b);
          (RunPushTrial(t).standing ? a : b) = t.impulse;
        }
        found[k] = a;
      }
      std::printf("dir %3d largest impulse: balance %6.1f N s, posture %6.1f N s\n", dir, found[0],
                  found[1]);
      continue;
    }
    t.impulse = impulse;
    const PushOutcome r = RunPushTrial(t);
    std::printf("dir %3d impulse %5.1f: %s tilt %5.2f deg, base settles %6.3f s, torque settles "
                "%6.3f s (peak %.1f N m)\n",
                dir, impulse, r.standing ? "standing" : "FELL    ", r.max_tilt / kDeg,
                r.base_settle, r.torque_settle, r.torque_peak);
  }
}

}  // namespace
}  // namespace ohrp::controllers::testing
