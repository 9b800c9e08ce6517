// The built `balance` program, unchanged, on the hardware path: hw_emulator (the boards, a
// MuJoCo HRP-1S behind them, real time) <- UDP -> hw_driver with libohrp_io_udp.so (2 ms servo
// cycle, real-time pacing) <- segment -> balance. The emulator's log says whether the robot
// stands; faults injected in the emulator (a stuck F/T sensor, a silent board) reach balance as
// the driver's kBoardFault status. Skipped when the hardware programs are not built. Bounds are
// generous in wall time: the machine may be loaded.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "fake_robot.h"
#include "hw_chain.h"

namespace ohrp::controllers::testing {
namespace {

// the producer time balance reports holding from, -1 when it did not hold
double HoldTime(const std::string& out) {
  const std::string key = "HELD the last commanded posture from t = ";
  const std::size_t at = out.find(key);
  return at == std::string::npos ? -1.0 : std::atof(out.c_str() + at + key.size());
}

class BalanceHw : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string p = MissingHwProgram("balance"); !p.empty())
      GTEST_SKIP() << p << " is not built";
  }
};

// 2. the program that stands on sim_host stands the emulated robot through the driver
TEST_F(BalanceHw, StandsThroughHwDriverAndUdp) {
  const Chain c = RunChain("bal_hw", {"balance"}, {}, 7.0);
  ASSERT_EQ(c.driver, 0) << Diagnosis(c);
  ASSERT_EQ(c.controller, 0) << Diagnosis(c);
  EXPECT_EQ(c.emulator, 130) << Diagnosis(c);
  EXPECT_NE(c.controller_out.find("balance: stood"), std::string::npos) << Diagnosis(c);
  EXPECT_EQ(c.controller_out.find("HELD"), std::string::npos) << Diagnosis(c);
  ASSERT_FALSE(c.summary.is_discarded()) << Diagnosis(c);
  EXPECT_EQ(c.summary["safe_mode"], false) << Diagnosis(c);
  EXPECT_EQ(c.summary["rejected_commands"], 0) << Diagnosis(c);
  // standing (ramp, settle, centring done by 3.5 s): within 2 cm of the keyframe's height,
  // 3 mm of spread, upright within 3 degrees, until the driver's end (7 s)
  const auto s = Span(c, 3.5, 6.9);
  EXPECT_NEAR(s[0], kHalfSitHeight, 0.02);
  EXPECT_LT(s[1] - s[0], 0.003);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] balance on hw_driver + udp + hw_emulator: base z %.4f..%.4f m, tilt "
              "max %.2f deg in [3.5, 6.9] s; driver: %s late commands, %s deadline misses\n%s",
              s[0], s[1], s[2], c.summary["late_commands"].dump().c_str(),
              c.summary["deadline_misses"].dump().c_str(), c.controller_out.c_str());
}

// issue 31: G1 through its robot profile, the same chain: the emulator and the driver take the
// profile as their model, balance its stance, servo and feed-forward; standing within 2 cm of
// the profile's stance height (0.763 m; the soft soles sink it by 3 mm), upright within 3 deg
TEST_F(BalanceHw, G1ThroughItsProfileStandsThroughHwDriverAndUdp) {
  if (ExternalDir().empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
  const std::string g1 = std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml";
  const Chain c = RunChainOn({g1, "stand"}, "bal_hw_g1",
                             {"balance", "--model", g1, "--keyframe", "stand"},
                             {"--period", "0.002"}, 7.0);  // G1's timestep
  ASSERT_EQ(c.driver, 0) << Diagnosis(c);
  ASSERT_EQ(c.controller, 0) << Diagnosis(c);
  EXPECT_NE(c.controller_out.find("balance: stood"), std::string::npos) << Diagnosis(c);
  ASSERT_FALSE(c.summary.is_discarded()) << Diagnosis(c);
  EXPECT_EQ(c.summary["rejected_commands"], 0) << Diagnosis(c);
  const auto s = Span(c, 3.5, 6.9);
  EXPECT_NEAR(s[0], 0.763, 0.02);
  EXPECT_LT(s[1] - s[0], 0.005);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] G1 balance on hw_driver + udp + hw_emulator: base z %.4f..%.4f m, "
              "tilt max %.2f deg in [3.5, 6.9] s; driver: %s deadline misses\n%s",
              s[0], s[1], s[2], c.summary["deadline_misses"].dump().c_str(),
              c.controller_out.c_str());
}

// 5. a stuck ankle F/T sensor (stale values): the driver flags kBoardFault, balance holds its
// last posture from then on and says so; the held robot keeps standing
TEST_F(BalanceHw, AStuckAnkleSensorLatchesTheHold) {
  const Chain c = RunChain("bal_hw_stuck", {"balance"}, {"--stuck", "ft0@4.5"}, 6.5,
                           kFaultTolerance);
  ASSERT_EQ(c.driver, 0) << c.driver_out;
  ASSERT_EQ(c.controller, 0) << c.controller_out;
  // (driver time, which starts a few cycles before the emulator's robot time)
  EXPECT_GE(HoldTime(c.controller_out), 4.5) << c.controller_out;
  EXPECT_LT(HoldTime(c.controller_out), 4.7) << c.controller_out;
  EXPECT_NE(c.controller_out.find("board fault reported by the producer"), std::string::npos)
      << c.controller_out;
  EXPECT_EQ(c.summary["rejected_commands"], 0);
  const auto s = Span(c, 4.6, 6.4);
  EXPECT_NEAR(s[0], kHalfSitHeight, 0.02);
  EXPECT_LT(s[1] - s[0], 0.003);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] stuck ft0 at 4.5 s: base z %.4f..%.4f m, tilt max %.2f deg after\n%s",
              s[0], s[1], s[2], c.controller_out.c_str());
}

// a board falling silent: the driver's safe mode ends the run (exit 6); balance held from the
// silence on (kBoardFault, never NaN: the driver rejected no command)
TEST_F(BalanceHw, ASilentBoardLatchesTheHoldBeforeTheDriversSafeMode) {
  const Chain c = RunChain("bal_hw_silent", {"balance"}, {"--silent", "2@4.5"}, 7.0,
                           kFaultTolerance);
  ASSERT_EQ(c.driver, 6) << c.driver_out;
  // the plugin marks the board silent after timeout_ms (100 ms): until then the driver
  // publishes the board's last values (stale), which balance cannot tell from fresh ones
  EXPECT_GE(HoldTime(c.controller_out), 4.6) << c.controller_out;
  EXPECT_LT(HoldTime(c.controller_out), 4.8) << c.controller_out;
  EXPECT_EQ(c.controller, 6) << "balance's exit code when the producer ends in failure";
  EXPECT_NE(c.controller_out.find("board fault reported by the producer"), std::string::npos)
      << c.controller_out;
  EXPECT_EQ(c.summary["rejected_commands"], 0);
  std::printf("[ figures  ] silent board 2 at 4.5 s: driver exit %d, balance exit %d\n%s",
              c.driver, c.controller, c.controller_out.c_str());
}

}  // namespace
}  // namespace ohrp::controllers::testing
