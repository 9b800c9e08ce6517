// Tests how hw_driver recovers, as a process with the real binary and the fake boards
// (fake_io.cc): after a lost controller with --on-controller-loss wait, the servos go off and
// come on again, holding the measured positions, when a new controller attaches; a board reset
// re-arms the boards and servos on again when the reads are clean, instead of ending the run;
// a controller stopped past the watchdog is dropped and, resumed, exits non-zero.
#include <string>
#include <vector>

#include "driver_process.h"

namespace ohrp::hw {
namespace {

using testing::HwDriverProcess;
using testing::Peek;
using testing::Written;

// the summary's event names, in order
std::vector<std::string> EventNames(const nlohmann::json& summary) {
  std::vector<std::string> names;
  for (const auto& e : summary["events"]) names.push_back(e["event"].get<std::string>());
  return names;
}

// true when `want` appears in `names` in this order (other names may come between)
bool InOrder(const std::vector<std::string>& names, const std::vector<std::string>& want) {
  size_t at = 0;
  for (const std::string& n : names) {
    if (at < want.size() && n == want[at]) ++at;
  }
  return at == want.size();
}

std::string Join(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += n + " ";
  return s;
}

// the first write with servos on after the first servo-off write from index `from`; -1 if none
long ServoOnAfterServoOff(const std::vector<Written>& rec, size_t from = 0) {
  size_t i = from;
  while (i < rec.size() && rec[i].servo != 0) ++i;
  while (i < rec.size() && rec[i].servo != 1) ++i;
  return i < rec.size() ? static_cast<long>(i) : -1;
}

//---------------- a lost controller, --on-controller-loss wait ----------------

TEST_F(HwDriverProcess, AfterALostControllerANewOneAttachesAndTheServosComeOnAgain) {
  Start({"--duration", "120", "--watchdog-cycles", "1000000", "--safe-time", "0.05",
         "--on-controller-loss", "wait"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  ohrp::testing::Pipe answered;
  child_ = Controller(Hold(0.2, 0.3), 100, &answered);
  answered.CloseSendEnd();  // the controller's exit ends the wait
  ASSERT_TRUE(answered.Receive(60)) << Stderr();  // 100 cycles answered
  ohrp::testing::Kill(&child_);

  // safe mode, then servos off and waiting: the run goes on
  const uint32_t off = shm::status::kServoOff | shm::status::kNoController;
  ASSERT_TRUE(WaitUntil([&] { return (peek.status() & off) == off; })) << Stderr();
  EXPECT_TRUE(ohrp::testing::Running(pid_)) << Stderr();
  // a new controller: servo-on again, and its commands act
  child_ = Controller(Hold(-0.4, 0.5));
  EXPECT_TRUE(WaitUntil([&] {
    return std::fabs(peek.get().sensors.q[0] + 0.4) < 1e-12 &&
           std::fabs(peek.get().sensors.q[1] - 0.5) < 1e-12;
  })) << Stderr();
  EXPECT_FALSE(peek.status() & shm::status::kServoOff);
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0);

  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "interrupted");
  EXPECT_EQ(s["recoveries"].get<int>(), 1);
  EXPECT_TRUE(s["safe_mode"].get<bool>());
  const auto names = EventNames(s);
  EXPECT_TRUE(InOrder(names, {"servo_on", "controller_attached", "controller_died", "safe_mode",
                              "servo_off", "waiting_for_controller", "servo_on",
                              "controller_attached", "stop_requested", "servo_off"}))
      << Join(names);
  // the servo-on sequence again: the measured positions held with the start's gains
  const auto rec = Records();
  const long on = ServoOnAfterServoOff(rec);
  ASSERT_GT(on, 0);
  EXPECT_NEAR(rec[on].q_ref[0], 0.2, 1e-12);
  EXPECT_NEAR(rec[on].q_ref[1], 0.3, 1e-12);
  EXPECT_DOUBLE_EQ(rec[on].kp[0], rec.front().kp[0]);
  EXPECT_NE(Stderr().find("waiting_for_controller"), std::string::npos) << Stderr();
}

//---------------- a controller stopped past its watchdog, then resumed ----------------

// posture stopped by SIGSTOP past the watchdog is dropped from the segment; resumed, it learns
// so and exits 7 (the controllers' "dropped"), whether the driver waits or ends
TEST_F(HwDriverProcess, AControllerStoppedPastTheWatchdogIsDroppedAndExitsNonZeroWhenResumed) {
  for (const std::string policy : {"wait", "end"}) {
    Start({"--duration", "120", "--watchdog-cycles", "20", "--safe-time", "0.05",
           "--on-controller-loss", policy});
    ASSERT_TRUE(WaitSegment()) << Stderr();
    Peek peek(segment_);
    const std::string pose = Write("pose.yaml", "joints:\n  j1: 0.5\n  j2: -0.3\n");
    child_ = Exec({std::string(OHRP_BIN_DIR) + "/posture", "--segment", segment_, "--pose", pose,
                   "--ramp", "0.05", "--attach-timeout", "10"},
                  Path("posture.out"));
    ASSERT_TRUE(WaitUntil([&] { return std::fabs(peek.get().sensors.q[0] - 0.5) < 1e-9; }))
        << Read("posture.out");
    kill(child_, SIGSTOP);
    // the watchdog trips and the driver lets the controller go
    ASSERT_TRUE(WaitUntil([&] { return peek.get().header.controller_pid == 0; })) << Stderr();
    if (policy == "end") {
      EXPECT_EQ(Wait(), 5) << Stderr();
    }
    kill(child_, SIGCONT);
    EXPECT_EQ(WaitExit(&child_), 7) << policy << ": " << Read("posture.out");
    EXPECT_NE(Read("posture.out").find("dropped this controller"), std::string::npos)
        << Read("posture.out");
    if (policy == "wait") {
      kill(pid_, SIGINT);
      EXPECT_EQ(Wait(), 130) << Stderr();
    }
    EXPECT_TRUE(InOrder(EventNames(Summary()), {"controller_silent", "safe_mode", "servo_off"}))
        << Join(EventNames(Summary()));
  }
}

//---------------- a board reset ----------------

TEST_F(HwDriverProcess, ABoardResetRearmsTheBoardsAndServosOnAgainInsteadOfEndingTheRun) {
  Start({"--io-arg", "reset_at=300", "--board-timeout-cycles", "5", "--safe-time", "0.05",
         "--duration", "120", "--watchdog-cycles", "1000000"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  child_ = Controller(Hold(0.2, 0.3));
  // the reset at read 300, 50 ms of safe mode, the re-arm, 5 clean reads: then servos on again
  const uint32_t not_running = shm::status::kServoOff | shm::status::kHolding;
  EXPECT_TRUE(WaitUntil([&] { return peek.cycle() > 600 && !(peek.status() & not_running); }))
      << Stderr();
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0);

  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "interrupted");
  EXPECT_EQ(s["recoveries"].get<int>(), 1);
  EXPECT_EQ(EventCycle(s, "board_reset"), 300) << s.dump(1);
  const long rearm = EventCycle(s, "board_rearm");
  ASSERT_GT(rearm, 300) << s.dump(1);
  EXPECT_TRUE(InOrder(EventNames(s), {"board_reset", "safe_mode", "servo_off", "board_rearm",
                                      "servo_on", "stop_requested", "servo_off"}))
      << Join(EventNames(s));
  for (const auto& e : s["events"]) {
    if (e["event"] == "safe_mode") {
      EXPECT_EQ(e["value"].get<long>(), 2);  // hw::kSafeBoardReset
    }
    // servo-on again after 5 clean reads: the servo-off cycle re-armed the board
    if (e["event"] == "servo_on" && e["value"].get<long>() == 1) {
      EXPECT_EQ(e["cycle"].get<long>(), rearm + 5);
    }
  }
  // the boards got the re-arm (every servo off), then the measured hold, then the controller's
  // commands again
  const auto rec = Records();
  size_t after_reset = 0;
  while (after_reset < rec.size() && rec[after_reset].reads <= 300) ++after_reset;
  const long on = ServoOnAfterServoOff(rec, after_reset);
  ASSERT_GT(on, 0);
  EXPECT_NEAR(rec[on].q_ref[0], 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(rec[on].kp[0], rec.front().kp[0]);
  bool commanded = false;
  for (size_t i = on + 1; i < rec.size(); ++i) commanded = commanded || rec[i].kp[0] == 10.0;
  EXPECT_TRUE(commanded) << "the controller's gains (kp 10) never reached the boards again";
}

}  // namespace
}  // namespace ohrp::hw
