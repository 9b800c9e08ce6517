// The built `walk` program, unchanged, on the hardware path (issue 10, item 3): hw_emulator
// (a MuJoCo HRP-1S behind the boards, real time) <- UDP -> hw_driver (2 ms servo cycle) <-
// segment -> walk, as balance_hw_test.cc does for balance (hw_chain.h). The emulator's log
// (ground truth, which walk never sees) says where the base went and whether it stayed up;
// the driver's summary says whether it saw a fault. Skipped when the hardware programs are
// not built. Bounds are generous in wall time: the machine may be loaded.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "fake_robot.h"
#include "hw_chain.h"

namespace ohrp::controllers::testing {
namespace {

// the walk's robot-time budget: stand up (1 s ramp, settle, centring), lower the CoM (1 s),
// the steps, the closing step and a second of standing at the end
constexpr double kStraightDuration = 16.0;  // [s]
constexpr double kTurnDuration = 16.0;      // [s]

class WalkHw : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string p = MissingHwProgram("walk"); !p.empty())
      GTEST_SKIP() << p << " is not built";
  }
};

// the base's pose in the emulator's log: the first row with all servos on, and the last row
const EmulatorRow& FirstOn(const Chain& c) {
  for (const EmulatorRow& r : c.rows)
    if (r.on == 29) return r;
  return c.rows.front();
}

// the chain ended cleanly: driver and walk exit 0, no fault, no rejected command
void ExpectCleanRun(const Chain& c) {
  EXPECT_EQ(c.driver, 0) << Diagnosis(c);
  EXPECT_EQ(c.controller, 0) << Diagnosis(c);
  EXPECT_EQ(c.emulator, 130) << Diagnosis(c);
  ASSERT_FALSE(c.summary.is_discarded()) << Diagnosis(c);
  EXPECT_EQ(c.summary["safe_mode"], false) << Diagnosis(c);
  EXPECT_EQ(c.summary["rejected_commands"], 0) << Diagnosis(c);
  EXPECT_EQ(c.controller_out.find("HELD"), std::string::npos) << Diagnosis(c);
  EXPECT_NE(c.controller_out.find("walk: done, standing on both feet"), std::string::npos)
      << Diagnosis(c);
}

// not fallen: the base stays above 0.6 m and upright within 5 deg with all servos on (the
// scenarios' not_fallen check); {z_lo, z_hi, tilt_max}
std::array<double, 3> ExpectUpright(const Chain& c, double t_end) {
  const auto s = Span(c, 0.5, t_end);
  EXPECT_GT(s[0], 0.6) << "base height [m]";
  EXPECT_LT(s[2], 5.0) << "tilt [deg]";
  return s;
}

// `goal 1 0 0`: the base ends about 1 m ahead of where it stood, on the same line and heading
TEST_F(WalkHw, WalksOneMetreForwardThroughHwDriverAndUdp) {
#ifdef OHRP_SANITIZE
  // walk's cycle plus the self-collision guard's braking check take too long at -O1 with ASan
  // for the driver's real-time cycle: late commands, then "a board did not do what it was
  // commanded" (issue 29's guard; the lock-step walk tests run in the sanitizer build)
  GTEST_SKIP() << "walk through hw_driver is not real time in a sanitizer build";
#endif
  const Chain c = RunChain("walk_hw", {"walk", "--ramp", "1.0", "--command", "goal 1 0 0"}, {},
                           kStraightDuration);
  ExpectCleanRun(c);
  ASSERT_FALSE(c.rows.empty());
  const EmulatorRow &a = FirstOn(c), &b = c.rows.back();
  EXPECT_NEAR(b.x - a.x, 1.0, 0.2) << "forward [m]";
  EXPECT_NEAR(b.y - a.y, 0.0, 0.2) << "sideways [m]";
  EXPECT_NEAR(b.yaw - a.yaw, 0.0, 5.0) << "heading [deg]";
  const auto s = ExpectUpright(c, kStraightDuration - 0.1);
  std::printf("[ figures  ] walk goal 1 0 0 on hw_driver + udp + hw_emulator: base moved "
              "(%.3f, %.3f) m, yaw %.2f deg; base z %.3f..%.3f m, tilt max %.2f deg; driver: %s "
              "late commands, %s deadline misses\n%s",
              b.x - a.x, b.y - a.y, b.yaw - a.yaw, s[0], s[1], s[2],
              c.summary["late_commands"].dump().c_str(),
              c.summary["deadline_misses"].dump().c_str(), c.controller_out.c_str());
}

// `goal 0 0 90`: a quarter turn on the spot
TEST_F(WalkHw, TurnsNinetyDegreesThroughHwDriverAndUdp) {
#ifdef OHRP_SANITIZE
  // walk's cycle plus the self-collision guard's braking check take too long at -O1 with ASan
  // for the driver's real-time cycle: late commands, then "a board did not do what it was
  // commanded" (issue 29's guard; the lock-step walk tests run in the sanitizer build)
  GTEST_SKIP() << "walk through hw_driver is not real time in a sanitizer build";
#endif
  const Chain c = RunChain("walk_hw_turn", {"walk", "--ramp", "1.0", "--command", "goal 0 0 90"},
                           {}, kTurnDuration);
  ExpectCleanRun(c);
  ASSERT_FALSE(c.rows.empty());
  const EmulatorRow &a = FirstOn(c), &b = c.rows.back();
  EXPECT_NEAR(std::remainder(b.yaw - a.yaw, 360.0), 90.0, 5.0) << "heading [deg]";
  EXPECT_LT(std::hypot(b.x - a.x, b.y - a.y), 0.2) << "drift [m]";
  const auto s = ExpectUpright(c, kTurnDuration - 0.1);
  std::printf("[ figures  ] walk goal 0 0 90 on the hardware path: yaw %.2f deg, base moved "
              "(%.3f, %.3f) m; base z %.3f..%.3f m, tilt max %.2f deg\n%s",
              b.yaw - a.yaw, b.x - a.x, b.y - a.y, s[0], s[1], s[2], c.controller_out.c_str());
}

// issue 31: G1 through its robot profile walks the scenario g1_walk_forward's 5 m through the
// chain: the emulator at G1's 2 ms timestep on the soft soles (--contact auto, as sim_host), the
// driver and walk at the scenario's 4 ms period. Judged as the scenario: within 0.2 m and 5 deg
// of the goal, and not fallen (the emulator's truth: base above 0.6 m, tilt under 5 deg with all
// servos on, below the 7.2 deg at which G1's CoM, 0.672 m up, leaves its 0.085 m sole reach;
// the driver's own IMU fall check, --fall-tilt, ends the run with exit 10 otherwise).
// DISABLED: not reliable yet. Of 10 such runs 3 reached the goal (4.96-4.98 m, tilt at most
// 3.2 deg, joint by joint as sim_host's g1_walk_forward), 7 fell: walk's hip strategy swings
// the waist roll to its 0.35 rad clamp (sim_host too reaches 11 deg of torso offset at 4 ms)
// and the chain's timing (a cycle's delay, late commands) tips it (docs/robots.md "Through
// hw_driver + hw_emulator"). With the hip strategy's clamp and share derived from the model
// (hip_strategy.h) 0 of 10 on a shared machine (load 8-12, up to 183 deadline misses), and 0 of 5
// with the old 0.35 rad clamp in the same conditions (docs/robots.md "The hip strategy from the
// robot"). Run it with --gtest_also_run_disabled_tests.
TEST_F(WalkHw, DISABLED_G1ThroughItsProfileWalksFiveMetresThroughHwDriverAndUdp) {
#ifdef OHRP_SANITIZE
  GTEST_SKIP() << "walk through hw_driver is not real time in a sanitizer build";
#endif
  if (ExternalDir().empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
  constexpr double kDuration = 42.0;  // the scenario's
  const std::string g1 = std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml";
  const Chain c = RunChainOn({g1, "stand", 0.004}, "walk_hw_g1",
                             {"walk", "--model", g1, "--stance-keyframe", "stand", "--ramp", "1.0",
                              "--command", "goal 5 0 0"},
                             {"--period", "0.002"}, kDuration);
  ExpectCleanRun(c);
  ASSERT_FALSE(c.rows.empty());
  const EmulatorRow &a = FirstOn(c), &b = c.rows.back();
  EXPECT_NEAR(b.x - a.x, 5.0, 0.2) << "forward [m]";
  EXPECT_NEAR(b.y - a.y, 0.0, 0.2) << "sideways [m]";
  EXPECT_NEAR(b.yaw - a.yaw, 0.0, 5.0) << "heading [deg]";
  const auto s = ExpectUpright(c, kDuration - 0.1);
  std::printf("[ figures  ] G1 walk goal 5 0 0 on hw_driver (4 ms) + udp + hw_emulator (2 ms, "
              "soft soles): base moved (%.3f, %.3f) m, yaw %.2f deg; base z %.3f..%.3f m, tilt "
              "max %.2f deg; driver: %s late commands, %s deadline misses\n%s",
              b.x - a.x, b.y - a.y, b.yaw - a.yaw, s[0], s[1], s[2],
              c.summary["late_commands"].dump().c_str(),
              c.summary["deadline_misses"].dump().c_str(), c.controller_out.c_str());
}

}  // namespace
}  // namespace ohrp::controllers::testing
