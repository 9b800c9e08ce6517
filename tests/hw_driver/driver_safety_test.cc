// Tests hw_driver's safety as a process, with the real binary and the fake boards (fake_io.cc):
// a killed or silent controller, a silent board, a NaN from a board, the emergency stop input
// and SIGUSR2 put the robot into safe mode or turn the servos off.
#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::Clock;
using testing::HwDriverProcess;
using testing::Peek;
using testing::Since;
using ohrp::testing::Kill;
using ohrp::testing::Pipe;

//---------------- safety ----------------

TEST_F(HwDriverProcess, KilledControllerTripsTheSafeModeWithinTwoCycles) {
  Start({"--duration", "60", "--watchdog-cycles", "1000000", "--safe-time", "0.1"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  Pipe answered;
  child_ = Controller(Hold(0.2, 0.3), 100, &answered);
  answered.CloseSendEnd();  // the controller's exit ends the wait
  ASSERT_TRUE(answered.Receive(60)) << Stderr();  // 100 cycles answered
  Kill(&child_);  // reaped: from here its death is observable
  const uint64_t observable = peek.cycle();
  EXPECT_EQ(Wait(), 5) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto s = Summary();
  ASSERT_TRUE(s["safe_mode"].get<bool>()) << s.dump(1);
  const long safe = s["safe_mode_cycle"].get<long>();
  EXPECT_EQ(EventCycle(s, "controller_died"), safe);
  EXPECT_LE(safe, static_cast<long>(observable) + 2)
      << "safe mode at cycle " << safe << ", death observable from cycle " << observable;
  std::printf("controller death observable at cycle %lu, safe mode at cycle %ld\n",
              static_cast<unsigned long>(observable), safe);
  // safe mode: held references with damping gains, then servos off; status said so
  const auto rec = Records();
  ASSERT_FALSE(rec.empty());
  EXPECT_EQ(rec.back().servo, 0);
  EXPECT_EQ(rec[rec.size() - 2].servo, 1);
  EXPECT_NEAR(rec[rec.size() - 2].q_ref[0], 0.2, 1e-12);
  EXPECT_LT(rec[rec.size() - 2].kp[0], 10.0 * 1e3);
  const uint32_t last = peek.status();
  EXPECT_TRUE(last & shm::status::kServoOff);
  EXPECT_TRUE(last & shm::status::kShuttingDown);
}

TEST_F(HwDriverProcess, SilentControllerTripsTheSafeModeAfterTheWatchdogCycles) {
  Start({"--duration", "60", "--watchdog-cycles", "10", "--safe-time", "0.05"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  Pipe answered;
  child_ = Controller(Hold(0.2, 0.3), 50, &answered);
  answered.CloseSendEnd();  // the controller's exit ends the wait
  // a loaded machine (the sanitizer build on two CPUs) may make the controller late by the 10
  // cycles before it has answered 50: then the driver trips on the same rule, the controller
  // sees the run end and exits without sending, and there is no one left to stop. Either way
  // only the rule is checked, on the driver's own counts.
  if (answered.Receive(60)) kill(child_, SIGSTOP);  // alive, but silent
  const int code = Wait();
  Kill(&child_);
  ASSERT_EQ(code, 5) << Stderr();
  const auto s = Summary();
  const long silent = EventCycle(s, "controller_silent");
  ASSERT_GE(silent, 0) << s.dump(1);
  EXPECT_EQ(s["safe_mode_cycle"].get<long>(), silent);
  for (const auto& e : s["events"]) {
    if (e["event"] == "controller_silent") {
      EXPECT_EQ(e["value"].get<long>(), 10);
    }
  }
  // the last accepted answer was 10 cycles before the trip
  const uint64_t last_answer = peek.get().sensors.last_command_cycle;
  EXPECT_EQ(static_cast<long>(last_answer) + 10, silent);
  EXPECT_EQ(Records().back().servo, 0);
}

TEST_F(HwDriverProcess, SilentBoardTripsTheSafeModeWithinTheConfiguredCycles) {
  Start({"--io-arg", "silent_at=300", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "60"});
  EXPECT_EQ(Wait(), 6) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "board_fault");
  EXPECT_EQ(EventCycle(s, "board_silent"), 300);
  const long safe = s["safe_mode_cycle"].get<long>();
  EXPECT_EQ(safe, 304);  // the 5th silent cycle
  EXPECT_EQ(Records().back().servo, 0);
  EXPECT_NE(Stderr().find("board silent"), std::string::npos) << Stderr();
}

// a NaN from a board is no valid read: safe mode as for a silent board, but the event and the
// safe mode name the NaN and the board, not "board_silent (board mask 0x0)"
TEST_F(HwDriverProcess, NanFromABoardTripsTheSafeModeNamingTheNanAndTheBoard) {
  Start({"--io-arg", "nan_at=300", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "60"});
  EXPECT_EQ(Wait(), 6) << Stderr();
  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "board_fault");
  EXPECT_EQ(EventCycle(s, "board_non_finite"), 300) << s.dump(1);
  EXPECT_EQ(EventCycle(s, "board_silent"), -1) << s.dump(1);
  for (const auto& e : s["events"]) {
    if (e["event"] == "board_non_finite") {
      EXPECT_EQ(e["value"].get<long>(), 1);
    }
    if (e["event"] == "safe_mode") {
      EXPECT_EQ(e["value"].get<long>(), 6);  // kSafeBoardNonFinite
    }
  }
  EXPECT_EQ(s["safe_mode_cycle"].get<long>(), 304);
  EXPECT_EQ(Records().back().servo, 0);
  EXPECT_NE(Stderr().find("board_non_finite (NaN or inf from board mask 0x1)"), std::string::npos)
      << Stderr();
  EXPECT_NE(Stderr().find("safe_mode (NaN or inf from a board)"), std::string::npos) << Stderr();
  // and the joint that read it
  bool named = false;
  for (const auto& e : s["events"]) {
    if (e["event"] != "implausible_reading") continue;
    named = true;
    EXPECT_EQ(e["joint"], 0);
    EXPECT_EQ(e["reading"], "nan");
    EXPECT_EQ(e["cycle"], 300);
  }
  EXPECT_TRUE(named) << s.dump(1);
}

TEST_F(HwDriverProcess, EmergencyStopInputTurnsTheServosOffAtOnce) {
  Start({"--io-arg", "estop_at=200", "--duration", "60"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  EXPECT_EQ(Wait(), 7) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  const auto rec = Records();
  ASSERT_EQ(rec.size(), 201u);
  EXPECT_EQ(rec[199].servo, 1);
  EXPECT_EQ(rec[200].reads, 201u);  // the write of the very cycle that read the e-stop
  EXPECT_EQ(rec[200].servo, 0);
  const uint32_t last = peek.status();
  EXPECT_TRUE(last & shm::status::kEmergencyStop);
  EXPECT_TRUE(last & shm::status::kServoOff);
  EXPECT_EQ(Summary()["outcome"], "emergency_stop");
}

TEST_F(HwDriverProcess, Sigusr2IsAnEmergencyStop) {
  Start({"--duration", "60"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  const auto t0 = Clock::now();
  while (peek.cycle() < 50 && Since(t0) < 20) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  kill(pid_, SIGUSR2);
  EXPECT_EQ(Wait(), 7) << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
  EXPECT_EQ(Records().back().servo, 0);
  EXPECT_NE(Stderr().find("SIGUSR2"), std::string::npos) << Stderr();
}

}  // namespace
}  // namespace ohrp::hw
