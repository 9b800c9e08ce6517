// Tests how hw_driver recovers, as a process with the real binary and the fake boards
// (fake_io.cc): after a lost controller with --on-controller-loss wait, the servos go off and
// come on again, holding the measured positions, when a new controller attaches; a board reset
// is held through (re-arm, ramp back), instead of a safe mode;
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

// A board reset is held through: the write of the reset's cycle re-arms the board (every
// servo of the reset board off: the fake's boards are one), the next clean read turns them on
// again where they are measured, ramped back to the controller's references; no safe mode, the
// run goes on (before: a safe mode with the reset joints limp for --safe-time).
TEST_F(HwDriverProcess, ABoardResetIsReArmedAndRampedBackWithoutASafeMode) {
  Start({"--io-arg", "reset_at=300", "--board-timeout-cycles", "5", "--reset-ramp-time", "0.1",
         "--duration", "120", "--watchdog-cycles", "1000000"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  child_ = Controller(Hold(0.2, 0.3));
  const uint32_t not_running = shm::status::kServoOff | shm::status::kHolding;
  EXPECT_TRUE(WaitUntil([&] { return peek.cycle() > 600 && !(peek.status() & not_running); }))
      << Stderr();
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0);

  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "interrupted");
  EXPECT_EQ(s["safe_mode"], false);
  EXPECT_EQ(s["recoveries"].get<int>(), 1);
  EXPECT_EQ(EventCycle(s, "board_reset"), 300) << s.dump(1);
  EXPECT_EQ(EventCycle(s, "reset_hold"), 300) << s.dump(1);
  EXPECT_EQ(EventCycle(s, "safe_mode"), -1) << s.dump(1);
  EXPECT_TRUE(InOrder(EventNames(s), {"board_reset", "reset_hold", "servo_on", "reset_ramped",
                                      "stop_requested", "servo_off"}))
      << Join(EventNames(s));
  for (const auto& e : s["events"]) {
    // servo-on again at the first clean read after the re-arm
    if (e["event"] == "servo_on" && e["value"].get<long>() == 1) {
      EXPECT_EQ(e["cycle"].get<long>(), 301);
    }
  }
  // the writes: one with every servo off (the re-arm, in the reset's cycle), then servos on at
  // the measured position with the controller's gains, then the controller's commands again
  const auto rec = Records();
  size_t at = 0;
  while (at < rec.size() && rec[at].reads <= 300) ++at;
  ASSERT_LT(at + 2, rec.size());
  EXPECT_EQ(rec[at].reads, 301u);
  EXPECT_EQ(rec[at].servo, 0);
  EXPECT_EQ(rec[at + 1].servo, 1);
  EXPECT_NEAR(rec[at + 1].q_ref[0], 0.2, 1e-12);
  EXPECT_DOUBLE_EQ(rec[at + 1].kp[0], 10.0);
  int off = 0;
  for (size_t i = at; i + 3 < rec.size(); ++i) off += rec[i].servo == 0 ? 1 : 0;
  EXPECT_EQ(off, 1) << "the servos went off for more than the re-arm's cycle";
}

}  // namespace
}  // namespace ohrp::hw
