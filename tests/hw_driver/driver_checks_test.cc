// Tests the driver's verification of the boards (issue 28, item 2; board_checks.h) with the real
// binary and the fake boards (fake_io.cc): a servo the boards report off while commanded on, a
// joint that does not follow its reference, an implausible reading, the IMU saying the robot
// fell, and the safe mode's parameters checked so that the hold is one the servos take.
#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::HwDriverProcess;

// the first event named `name` of the summary (null when none)
nlohmann::json FirstEvent(const nlohmann::json& s, const std::string& name) {
  for (const auto& e : s["events"])
    if (e["event"] == name) return e;
  return nullptr;
}

TEST_F(HwDriverProcess, AServoTheBoardsReportOffWhileCommandedOnIsADisobeyingBoard) {
  Start({"--io-arg", "servo_off_at=200", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "60"});
  EXPECT_EQ(Wait(), 8) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "board_disobeys");
  const auto e = FirstEvent(s, "servo_mismatch");
  ASSERT_FALSE(e.is_null()) << s.dump(1);
  EXPECT_EQ(e["joint"], 1);
  EXPECT_EQ(e["joint_name"], "j2");
  EXPECT_EQ(e["reading"], 0.0);
  EXPECT_EQ(e["cycle"], 204);  // the 5th cycle of the disagreement
  EXPECT_EQ(s["safe_mode_cycle"], 204);
  EXPECT_NE(Stderr().find("servo_mismatch (board -1, joint 1 j2, read 0)"), std::string::npos)
      << Stderr();
}

TEST_F(HwDriverProcess, AJointThatDoesNotFollowItsReferenceIsATrackingError) {
  // joint 0 reads 0.3 rad away from its reference; the hold's default gains put the bound at
  // tau_max / kp (at least 0.05 rad); 0.1 s allowed
  Start({"--io-arg", "offset_at=200", "--tracking-time", "0.1", "--safe-time", "0.05",
         "--duration", "60"});
  EXPECT_EQ(Wait(), 8) << Stderr();
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "board_disobeys");
  const auto e = FirstEvent(s, "tracking_error");
  ASSERT_FALSE(e.is_null()) << s.dump(1);
  EXPECT_EQ(e["joint"], 0);
  EXPECT_NEAR(e["reading"].get<double>(), -0.3, 1e-9);  // reference - measured
  EXPECT_EQ(e["cycle"], 299);  // 100 cycles of 1 ms: reads 200..299
}

TEST_F(HwDriverProcess, APluginThatDoesNotReportServosIsNotHeldToThem) {
  // the replay's case: the servo states are not measured, the commands not followed
  Start({"--io-arg", "servo_off_at=200", "--io-arg", "offset_at=200", "--io-arg", "reports=0",
         "--board-timeout-cycles", "5", "--tracking-time", "0.05", "--duration", "0.5"});
  EXPECT_EQ(Wait(), 0) << Stderr();
  EXPECT_TRUE(FirstEvent(Summary(), "servo_mismatch").is_null());
  EXPECT_TRUE(FirstEvent(Summary(), "tracking_error").is_null());
}

TEST_F(HwDriverProcess, A1e300PositionIsNoValidReadAndItsEventNamesTheJoint) {
  Start({"--io-arg", "huge_at=300", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "60"});
  EXPECT_EQ(Wait(), 6) << Stderr();
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "board_fault");
  const auto e = FirstEvent(s, "implausible_reading");
  ASSERT_FALSE(e.is_null()) << s.dump(1);
  EXPECT_EQ(e["cycle"], 300);
  EXPECT_EQ(e["joint"], 1);
  EXPECT_EQ(e["reading"].get<double>(), 1e300);
  EXPECT_EQ(s["safe_mode_cycle"], 304);
  EXPECT_EQ(FirstEvent(s, "safe_mode")["value"], 7);  // kSafeBoardImplausible
  // the hold never took the 1e300 as a reference: every position reference within the range
  for (const auto& w : Records()) EXPECT_LE(std::fabs(w.q_ref[1]), 1.0 + 1e-9);
}

TEST_F(HwDriverProcess, TheImuTiltedPastTheLimitIsAFall) {
  Start({"--io-arg", "tilt_at=300", "--safe-time", "0.05", "--duration", "60"});
  EXPECT_EQ(Wait(), 10) << Stderr();
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "fall");
  const auto e = FirstEvent(s, "fall");
  ASSERT_FALSE(e.is_null()) << s.dump(1);
  EXPECT_EQ(e["cycle"], 300);
  EXPECT_NEAR(e["reading"].get<double>(), M_PI / 3, 1e-9);
  EXPECT_EQ(FirstEvent(s, "safe_mode")["value"], 9);  // kSafeFall
  EXPECT_NE(Stderr().find("fall (IMU tilt 60.0 deg)"), std::string::npos) << Stderr();
  // a larger limit: no fall
  fs::remove(Path("summary.json"));
  Start({"--io-arg", "tilt_at=300", "--fall-tilt", "1.2", "--duration", "0.5"});
  EXPECT_EQ(Wait(), 0) << Stderr();
}

// a board refusing what the guard accepted disobeys; refusing the safe mode's hold as well is
// a failure of its own: the robot was not held
TEST_F(HwDriverProcess, ARefusedCommandIsADisobeyingBoardAndARefusedHoldIsNamed) {
  Start({"--io-arg", "refuse_at=200", "--safe-time", "0.1", "--duration", "60"});
  EXPECT_EQ(Wait(), 8) << Stderr();
  const auto s = Summary();
  const auto refused = FirstEvent(s, "command_refused");
  ASSERT_FALSE(refused.is_null()) << s.dump(1);
  EXPECT_EQ(refused["cycle"], 200);
  EXPECT_EQ(refused["board"], 0);
  const auto hold = FirstEvent(s, "safe_mode_refused");
  ASSERT_FALSE(hold.is_null()) << s.dump(1);
  // 20 ms for the earlier refusals to pass (the safe mode's cycle, 200, is its first), then
  // 20 cycles of refusing the hold (1 ms cycles): 220..239
  EXPECT_EQ(hold["cycle"].get<long>(), 239);
  EXPECT_NE(Stderr().find("a board refused the damped hold"), std::string::npos) << Stderr();
}

TEST_F(HwDriverProcess, SafeModeGainsTheServosWouldRefuseAreRefusedBeforeTheRun) {
  for (const char* scale : {"1e308", "0", "nan", "-1"}) {
    Start({"--safe-kp-scale", scale, "--duration", "0.3"});
    EXPECT_EQ(Wait(), 2) << scale << ": " << Stderr();
    EXPECT_NE(Stderr().find("--safe-kp-scale"), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists(ShmPath()));
  }
  Start({"--safe-kd-scale", "1e308", "--duration", "0.3"});
  EXPECT_EQ(Wait(), 2) << Stderr();
  EXPECT_NE(Stderr().find("plausible range"), std::string::npos) << Stderr();
}

}  // namespace
}  // namespace ohrp::hw
