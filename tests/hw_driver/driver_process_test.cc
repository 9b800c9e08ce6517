// Tests hw_driver as a process, with the real binary: a controller (posture, or a robot
// adaptor in a forked child) attaches to its hardware segment and commands it; NaN commands are
// rejected and counted; its lateness is readable while it runs; it runs, warning once, without
// real-time permissions; its cycle statistics stay within lenient bounds in both wake modes.
// The boards are fake_io.cc, which records what the driver wrote. Checks count cycles, not
// wall time, so a loaded machine does not make them fail. The safety trips are tested in
// driver_safety_test.cc, the exit paths in driver_exit_test.cc, the models and the replay
// plugin in driver_models_test.cc.
#include "driver_process.h"

namespace ohrp::hw {
namespace {

namespace fs = std::filesystem;
using testing::HwDriverProcess;
using testing::Peek;
using testing::Written;

//---------------- attach and command ----------------

TEST_F(HwDriverProcess, PostureAttachesToTheHardwareSegmentAndCommandsIt) {
  Start({"--duration", "120", "--watchdog-cycles", "1000000", "--servo-off-time", "0.05"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  {
    const shm::SegmentHeader& h = peek.get().header;
    EXPECT_EQ(h.producer_kind, shm::ProducerKind::kHardware);
    EXPECT_EQ(h.producer_pid, pid_);
    EXPECT_EQ(h.njoint, 2);
    EXPECT_EQ(h.nforce, 1);
    EXPECT_EQ(h.nimu, 1);
    EXPECT_DOUBLE_EQ(h.physics_period, 0.0);
    EXPECT_DOUBLE_EQ(h.control_period, 0.001);
    EXPECT_DOUBLE_EQ(h.q_max[0], 1.5);
    EXPECT_DOUBLE_EQ(h.tau_max[1], 20.0);
  }
  const std::string pose = Write("pose.yaml", "joints:\n  j1: 0.5\n  j2: -0.3\n");
  child_ = Exec({std::string(OHRP_BIN_DIR) + "/posture", "--segment", segment_, "--pose", pose,
                 "--ramp", "0.2", "--attach-timeout", "10"},
                Path("posture.out"));
  // the fake boards' joints follow the references: wait until they reached the pose
  EXPECT_TRUE(WaitUntil([&] {
    return std::fabs(peek.get().sensors.q[0] - 0.5) < 1e-9 &&
           std::fabs(peek.get().sensors.q[1] + 0.3) < 1e-9;
  })) << Read("posture.out");
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0) << Read("posture.out");  // the producer ended its run
  EXPECT_FALSE(fs::exists(ShmPath()));

  const auto s = Summary();
  EXPECT_EQ(s["outcome"], "interrupted");
  EXPECT_GT(s["commands"].get<long>(), 100);
  EXPECT_GE(EventCycle(s, "controller_attached"), 0);
  // the boards got the pose, then the servo-off sequence
  const auto rec = Records();
  ASSERT_GT(rec.size(), 100u);
  EXPECT_EQ(rec.front().servo, 1);  // servo-on after the first valid read
  EXPECT_DOUBLE_EQ(rec.front().q_ref[0], 0.1);  // holding the measured position
  EXPECT_EQ(rec.back().servo, 0);
  const Written& last_on = rec[rec.size() - 2];
  EXPECT_EQ(last_on.servo, 1);
  EXPECT_NEAR(last_on.q_ref[0], 0.5, 1e-9);
  EXPECT_NEAR(last_on.q_ref[1], -0.3, 1e-9);
}

TEST_F(HwDriverProcess, NanCommandsAreRejectedCountedAndTheJointHolds) {
  Start({"--duration", "120", "--watchdog-cycles", "1000000", "--servo-off-time", "0.05"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  child_ = Controller(Hold(0.2, std::numeric_limits<double>::quiet_NaN()), -1, nullptr,
                      shm::status::kCommandRejected);
  EXPECT_TRUE(WaitUntil([&] {
    return peek.get().sensors.rejected_per_joint[1] > 10 &&
           std::fabs(peek.get().sensors.q[0] - 0.2) < 1e-12;
  }));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0);  // it saw kCommandRejected, then the producer stop
  const auto s = Summary();
  EXPECT_GT(s["rejected_per_joint"]["j2"].get<long>(), 10);
  EXPECT_EQ(s["rejected_per_joint"]["j1"].get<long>(), 0);
  bool reached = false;
  for (const Written& w : Records()) {
    ASSERT_TRUE(std::isfinite(w.q_ref[1]));
    if (w.servo == 1) {
      EXPECT_DOUBLE_EQ(w.q_ref[1], 0.1);  // j2 holds its servo-on position
    }
    reached = reached || std::fabs(w.q_ref[0] - 0.2) < 1e-12;
  }
  EXPECT_TRUE(reached);
}

// the controller's self-collision guard (issue 29): a held block begins a hold, an event with
// the guard's count and the pair's predicted distance; the data log's guard_holding says 1
TEST_F(HwDriverProcess, AGuardHoldIsAnEventAndALogColumn) {
  Start({"--duration", "120", "--watchdog-cycles", "1000000", "--servo-off-time", "0.05",
         "--log", Path("log.csv")});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  Peek peek(segment_);
  shm::CommandBlock held = Hold(0.2, 0.1);
  held.guard.holding = 1;
  held.guard.holds = 1;
  held.guard.distance = 0.0015;
  child_ = Controller(held);
  EXPECT_TRUE(WaitUntil([&] { return peek.get().sensors.last_command_cycle > 50; }));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(WaitExit(&child_), 0);
  const auto s = Summary();
  int begins = 0;
  for (const auto& e : s["events"]) {
    if (e["event"] != "guard_hold_begin") continue;
    ++begins;
    EXPECT_EQ(e["value"].get<long>(), 1) << e.dump();
    EXPECT_DOUBLE_EQ(e["reading"].get<double>(), 0.0015) << e.dump();
  }
  EXPECT_EQ(begins, 1) << s["events"].dump();
  const std::string log = Read("log.csv");
  const std::string header = log.substr(0, log.find('\n'));
  EXPECT_EQ(header.substr(header.rfind(',') + 1), "guard_holding") << header;
  EXPECT_NE(log.find(",1\n"), std::string::npos);  // rows held by the guard
}

//---------------- lateness readable while it runs ----------------

TEST_F(HwDriverProcess, LatenessIsReadableWhileItRunsFromTheStatsFileAndSigusr1) {
  Start({"--duration", "120", "--stats", Path("stats.json"), "--stats-interval", "0.05",
         "--servo-off-time", "0.01"});
  ASSERT_TRUE(WaitSegment()) << Stderr();
  nlohmann::json stats;
  EXPECT_TRUE(WaitUntil([&] {
    if (!fs::exists(Path("stats.json"))) return false;
    stats = nlohmann::json::parse(Read("stats.json"), nullptr, false);
    return !stats.is_discarded() && stats["lateness"]["count"].get<long>() > 20;
  }));
  EXPECT_EQ(stats["outcome"], "running");
  EXPECT_EQ(stats["state"], "active");
  EXPECT_TRUE(stats["lateness"].contains("p99_us"));
  kill(pid_, SIGUSR1);
  EXPECT_TRUE(WaitUntil([&] { return Stderr().find("p99") != std::string::npos; })) << Stderr();
  kill(pid_, SIGTERM);
  EXPECT_EQ(Wait(), 130) << Stderr();
  EXPECT_EQ(nlohmann::json::parse(Read("stats.json"))["outcome"], "interrupted");
}

//---------------- real-time set-up refused ----------------

TEST_F(HwDriverProcess, WithoutRealTimePermissionsItWarnsOnceAndRuns) {
  if (!fs::exists("/usr/bin/setpriv")) GTEST_SKIP() << "no setpriv";
  // the capabilities that permit SCHED_FIFO and mlockall dropped for the driver
  pid_ = Exec({"/usr/bin/setpriv", "--inh-caps=-all", "--bounding-set=-sys_nice,-ipc_lock", "--",
               std::string(OHRP_BIN_DIR) + "/hw_driver", "--model", model_, "--segment", segment_,
               "--io", FAKE_IO_PATH, "--duration", "0.2", "--quiet"},
              Path("driver.stderr"));
  const int code = Wait();
  const std::string e = Stderr();
  if (e.find("hw_driver") == std::string::npos && code != 0) {
    GTEST_SKIP() << "setpriv could not drop the capabilities here: " << e;
  }
  EXPECT_EQ(code, 0) << e;
  if (geteuid() == 0 || e.find("warning") != std::string::npos) {
    EXPECT_NE(e.find("warning: SCHED_FIFO 80 refused"), std::string::npos) << e;
  }
  EXPECT_FALSE(fs::exists(ShmPath()));
}

//---------------- the wake-up: cycle statistics within lenient bounds ----------------

// no timing figure is asserted here (the machine is shared; bench_rt measures): only that the
// cycles run, the spin-tail's margin stays within its bounds and its spin within its share
TEST_F(HwDriverProcess, CycleStatisticsStayWithinLenientBoundsInBothWakeModes) {
  Start({"--duration", "0.5", "--servo-off-time", "0.05"});
  EXPECT_EQ(Wait(), 0) << Stderr();
  auto s = Summary();
  const long cycles = s["cycles"].get<long>();
  EXPECT_GE(cycles + s["skipped_cycles"].get<long>(), 500);
  EXPECT_LE(s["deadline_misses"].get<long>(), cycles / 2) << s.dump(2);
  EXPECT_LT(s["lateness"]["p50_us"].get<double>(), 1000.0) << s.dump(2);
  EXPECT_EQ(s["wake"]["mode"], "spin-tail");
  EXPECT_GE(s["wake"]["margin_us"].get<double>(), 2.0);
  EXPECT_LE(s["wake"]["margin_us"].get<double>(), 200.0);
  EXPECT_GE(s["wake"]["spin_fraction"].get<double>(), 0.0);
  EXPECT_LE(s["wake"]["spin_fraction"].get<double>(), 0.25 + 0.01);  // the margin's bound
  EXPECT_NE(Stderr().find("(--wake spin-tail, margin "), std::string::npos) << Stderr();
  // the plain sleep: never spins
  Start({"--duration", "0.2", "--servo-off-time", "0.05", "--wake", "sleep"});
  EXPECT_EQ(Wait(), 0) << Stderr();
  s = Summary();
  EXPECT_EQ(s["wake"]["mode"], "sleep");
  EXPECT_EQ(s["wake"]["spin_fraction"].get<double>(), 0.0);
  EXPECT_GE(s["lateness"]["count"].get<long>(), 150);
}

TEST_F(HwDriverProcess, UnknownWakeModeExitsTwoNamingTheChoices) {
  Start({"--wake", "spin"});
  EXPECT_EQ(Wait(), 2) << Stderr();
  EXPECT_NE(Stderr().find("--wake: spin not in {spin-tail,sleep}"), std::string::npos)
      << Stderr();
  EXPECT_FALSE(fs::exists(ShmPath()));
}

}  // namespace
}  // namespace ohrp::hw
