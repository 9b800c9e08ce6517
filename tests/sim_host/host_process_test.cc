// Tests sim_host as a process: lock-step timing, command checks, and the faults (malformed
// model, dead controller, dead or interrupted sim_host, stale segment, a segment scribbled on),
// with the real binary.
#include <fcntl.h>
#include <sys/mman.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/process.h"
#include "shm_bridge/bridge.h"
#include "test_models.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

class SimHostProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = "simtest_" + std::to_string(getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove("/dev/shm/" + shm::SegmentObjectName(segment_));
    scene_ = testing::WriteTemp(testing::kTwoJointArm);
    err_ = testing::WriteTemp("", ".stderr");
  }
  void TearDown() override {
    ohrp::testing::Kill(&pid_);
    fs::remove("/dev/shm/" + shm::SegmentObjectName(segment_));
  }

  // starts sim_host on the arm model with `extra` options; stderr goes to err_
  void Start(std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", scene_,
                                     "--segment", segment_, "--physics-dt", "0.001",
                                     "--control-period", "0.002", "--progress", progress_};
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = ohrp::testing::Spawn(args, {.err = err_});
  }
  bool WaitSegment(double timeout = 5) {
    const auto t0 = Clock::now();
    while (Since(t0) < timeout) {
      if (fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_))) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  // waits for sim_host to end; returns its exit code, or -1 on timeout (left running)
  int Wait(double timeout = 10) { return ohrp::testing::WaitExit(&pid_, timeout); }
  std::string Stderr() {
    std::ifstream in(err_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  void Attach(shm::RobotAdaptor* a) {
    ASSERT_TRUE(WaitSegment());
    shm::Status st;
    for (int i = 0; i < 200; ++i) {
      st = a->open(segment_);
      if (st.ok()) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    FAIL() << st.message;
  }
  // a controller in another process that answers 10 cycles and dies without closing (its
  // claim stays on the segment: _exit); returns its exit code once it is reaped
  int RunDyingController() {
    const pid_t child = ohrp::testing::Spawn([&]() -> int {
      shm::RobotAdaptor a;
      for (int i = 0; i < 200 && !a.open(segment_).ok(); ++i) usleep(5000);
      shm::SensorBlock s{};
      for (int k = 0; k < 10; ++k) {
        if (a.read(&s) != shm::ReadResult::kOk) _exit(2);
        a.write(Hold(s, 2));
      }
      _exit(0);
    });
    return ohrp::testing::WaitExit(child, ohrp::testing::kNoTimeout);
  }
  static shm::CommandBlock Hold(const shm::SensorBlock& s, int n) {
    shm::CommandBlock c{};
    c.njoint = n;
    for (int i = 0; i < n; ++i) {
      c.joint[i].mode = shm::JointMode::kPosition;
      c.joint[i].q_ref = s.q[i];
      c.joint[i].kp = 100;
      c.joint[i].kd = 10;
    }
    return c;
  }

  std::string segment_, scene_, err_;
  std::string progress_ = "0";  // --progress [s]
  pid_t pid_ = -1;
};

TEST_F(SimHostProcess, MalformedModelExitsWithMujocosTextAndLeavesNoSegment) {
  scene_ = testing::WriteTemp("<mujoco><worldbody><body></worldbody>");
  Start({});
  EXPECT_EQ(Wait(), 2);
  const std::string e = Stderr();
  EXPECT_NE(e.find(scene_), std::string::npos) << e;
  EXPECT_NE(e.find("XML"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

TEST_F(SimHostProcess, MissingModelExitsNonZero) {
  scene_ = "/nonexistent/scene.xml";
  Start({});
  EXPECT_NE(Wait(), 0);
  EXPECT_NE(Stderr().find("/nonexistent/scene.xml"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

TEST_F(SimHostProcess, LockStepCommandsActFromTheNextCycle) {
  Start({"--duration", "1"});
  shm::RobotAdaptor a;
  Attach(&a);
  ASSERT_EQ(a.header().njoint, 2);
  EXPECT_EQ(a.header().producer_kind, shm::ProducerKind::kSimulation);
  shm::SensorBlock s{};
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  EXPECT_EQ(s.cycle, 0u);
  EXPECT_DOUBLE_EQ(s.time, 0.0);
  // a torque command answering cycle 0 is what the servo applies during cycle 1
  auto c = Hold(s, 2);
  c.joint[0].mode = shm::JointMode::kTorque;
  c.joint[0].tau_ff = 5.0;
  ASSERT_EQ(a.write(c), shm::ReadResult::kOk);
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  EXPECT_EQ(s.cycle, 1u);
  EXPECT_NEAR(s.time, 0.002, 1e-12);
  EXPECT_DOUBLE_EQ(s.tau[0], 5.0);
  // lock-step: every cycle is seen, none skipped, time advances by the control period
  for (uint64_t k = 2; k < 50; ++k) {
    ASSERT_EQ(a.write(c), shm::ReadResult::kOk);
    ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
    ASSERT_EQ(s.cycle, k);
    ASSERT_NEAR(s.time, 0.002 * k, 1e-9);
  }
  // the joint under a constant torque from t = 0 (the steps after cycle 0): q = tau t^2 / (2 I)
  // from rest, I = armature 2; semi-implicit Euler adds dt / t = 1 %
  const double t = s.time;
  EXPECT_NEAR(s.q[0], 5.0 * t * t / (2 * 2.0), 0.015 * 5.0 * t * t / 4.0);
  a.close();
}

TEST_F(SimHostProcess, NanCommandIsRejectedCountedAndTheJointHolds) {
  Start({"--duration", "5"});
  shm::RobotAdaptor a;
  Attach(&a);
  shm::SensorBlock s{};
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  auto c = Hold(s, 2);
  c.joint[1].q_ref = 0.3;
  c.joint[1].kd = 20;  // critically damped on j2's inertia of 1
  for (int k = 0; k < 500; ++k) {  // move j2 to 0.3 and let it settle
    ASSERT_EQ(a.write(c), shm::ReadResult::kOk);
    ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  }
  const double held = s.q[1];
  auto bad = c;
  bad.joint[1].q_ref = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < 20; ++k) {
    ASSERT_EQ(a.write(bad), shm::ReadResult::kOk);
    ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
    EXPECT_TRUE(s.status & shm::status::kCommandRejected);
  }
  EXPECT_EQ(s.rejected_per_joint[1], 20u);
  EXPECT_EQ(s.rejected_per_joint[0], 0u);
  EXPECT_EQ(s.rejected_commands, 20u);
  EXPECT_NEAR(s.q[1], held, 0.002);
  EXPECT_NEAR(s.q[1], 0.3, 0.002);
  EXPECT_TRUE(std::isfinite(s.q[1]));
  ASSERT_EQ(a.write(c), shm::ReadResult::kOk);
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  EXPECT_FALSE(s.status & shm::status::kCommandRejected);
}

TEST_F(SimHostProcess, ControllerDeathEndsTheRunWithinTheTimeout) {
  Start({"--duration", "100", "--on-controller-loss", "end", "--controller-timeout", "2"});
  ASSERT_TRUE(WaitSegment());
  ASSERT_EQ(RunDyingController(), 0);
  const auto t0 = Clock::now();
  EXPECT_EQ(Wait(), 5);
  EXPECT_LT(Since(t0), 0.5);  // noticed from the pid check, well before the 2 s timeout
  EXPECT_NE(Stderr().find("controller died"), std::string::npos) << Stderr();
  EXPECT_NE(Stderr().find("holding its last references"), std::string::npos);
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

TEST_F(SimHostProcess, AfterControllerLossANewControllerCanAttach) {
  Start({"--duration", "100", "--on-controller-loss", "wait"});
  ASSERT_TRUE(WaitSegment());
  ASSERT_EQ(RunDyingController(), 0);
  // attach only once sim_host has seen the loss (a quicker controller simply takes over)
  const auto t0 = Clock::now();
  while (Stderr().find("waiting for a new controller") == std::string::npos && Since(t0) < 2)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  shm::RobotAdaptor b;
  Attach(&b);
  shm::SensorBlock s{};
  ASSERT_EQ(b.read(&s), shm::ReadResult::kOk);
  EXPECT_GE(s.cycle, 10u);  // time went on from where the first controller left it
  EXPECT_TRUE(s.status & shm::status::kHolding);
  ASSERT_EQ(b.write(Hold(s, 2)), shm::ReadResult::kOk);
  ASSERT_EQ(b.read(&s), shm::ReadResult::kOk);
  EXPECT_FALSE(s.status & shm::status::kHolding);
  b.close();
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
}

// a controller stopped (SIGSTOP) past --controller-timeout is dropped: resumed after sim_host
// ended its run, its next read says so instead of a normal end (which made it exit 0)
TEST_F(SimHostProcess, AControllerStoppedPastTheTimeoutLearnsItWasDroppedWhenResumed) {
  Start({"--duration", "100", "--on-controller-loss", "end", "--controller-timeout", "0.2"});
  ASSERT_TRUE(WaitSegment());
  const pid_t child = ohrp::testing::Spawn([&]() -> int {
    shm::RobotAdaptor a;
    for (int i = 0; i < 200 && !a.open(segment_).ok(); ++i) usleep(5000);
    shm::SensorBlock s{};
    for (int k = 0; k < 10; ++k) {
      if (a.read(&s) != shm::ReadResult::kOk) _exit(2);
      a.write(Hold(s, 2));
    }
    raise(SIGSTOP);  // past the timeout; the test resumes it after sim_host has ended
    const shm::ReadResult r = a.read(&s);
    _exit(r == shm::ReadResult::kDropped ? 0 : 10 + static_cast<int>(r));
  });
  int st = 0;
  ASSERT_EQ(waitpid(child, &st, WUNTRACED), child);
  ASSERT_TRUE(WIFSTOPPED(st));
  EXPECT_EQ(Wait(), 5) << Stderr();
  EXPECT_NE(Stderr().find("did not answer within the timeout"), std::string::npos) << Stderr();
  kill(child, SIGCONT);
  const int code = ohrp::testing::WaitExit(child, ohrp::testing::kNoTimeout);
  ASSERT_GE(code, 0);  // reaped
  EXPECT_EQ(code, 0) << "10 + the ReadResult it got instead";
}

TEST_F(SimHostProcess, DeadSimHostMakesReadFailAndItsStaleSegmentIsReplaced) {
  Start({"--duration", "100"});
  shm::RobotAdaptor a;
  Attach(&a);
  shm::SensorBlock s{};
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  ASSERT_EQ(a.write(Hold(s, 2)), shm::ReadResult::kOk);
  ohrp::testing::Kill(&pid_);
  const auto t0 = Clock::now();
  shm::ReadResult r = shm::ReadResult::kOk;
  while (r == shm::ReadResult::kOk && Since(t0) < 3) r = a.read(&s);
  EXPECT_EQ(r, shm::ReadResult::kProducerGone);
  EXPECT_LT(Since(t0), 0.5);
  a.close();
  ASSERT_TRUE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));  // left behind
  Start({"--duration", "0.1", "--wait-controller", "0"});
  EXPECT_EQ(Wait(), 0);
  EXPECT_NE(Stderr().find("stale"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

// Another process scribbles random bytes on the segment's wake-up words while sim_host and a
// controller cycle: sim_host ends with exit code 5 and says why (it aborted with the old
// semaphores, or spun ignoring SIGTERM), even when its policy is to wait for a new controller;
// the controller's read or write reports it.
TEST_F(SimHostProcess, ScribbledWakeUpWordsEndTheRunWithAClearError) {
  Start({"--duration", "0", "--on-controller-loss", "wait"});
  ASSERT_TRUE(WaitSegment());
  const pid_t child = ohrp::testing::Spawn([&]() -> int {
    shm::RobotAdaptor a;
    for (int i = 0; i < 200 && !a.open(segment_).ok(); ++i) usleep(5000);
    shm::SensorBlock s{};
    for (;;) {
      shm::ReadResult r = a.read(&s);
      if (r == shm::ReadResult::kOk) r = a.write(Hold(s, 2));
      if (r != shm::ReadResult::kOk) _exit(10 + static_cast<int>(r));
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // cycling by now
  const int fd = open(("/dev/shm/" + shm::SegmentObjectName(segment_)).c_str(), O_RDWR);
  ASSERT_GE(fd, 0) << Stderr();
  void* map = mmap(nullptr, sizeof(shm::Segment), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
  close(fd);
  ASSERT_NE(map, MAP_FAILED);
  auto* sync = reinterpret_cast<unsigned char*>(&static_cast<shm::Segment*>(map)->sync);
  std::mt19937 random(7);
  const auto t0 = Clock::now();
  int code = -1;
  while (code == -1 && Since(t0) < 5) {
    for (std::size_t i = 0; i < sizeof(shm::Sync); ++i) sync[i] = static_cast<unsigned char>(random());
    code = Wait(0);  // one look, then 5 ms to the next scribble
    if (code == -1) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const double noticed = Since(t0);
  munmap(map, sizeof(shm::Segment));
  if (code == -1) kill(pid_, SIGTERM);  // a hung sim_host must still end on SIGTERM
  if (code == -1) code = Wait(2);
  EXPECT_EQ(code, 5) << "128 + a signal when killed (134: aborted), -1: hung\n" << Stderr();
  EXPECT_LT(noticed, 2.0);
  EXPECT_NE(Stderr().find("wake-up words were overwritten"), std::string::npos) << Stderr();
  const int controller = ohrp::testing::WaitExit(child, ohrp::testing::kNoTimeout);
  ASSERT_GE(controller, 0);  // reaped
  EXPECT_TRUE(controller == 10 + static_cast<int>(shm::ReadResult::kSyncCorrupted) ||
              controller == 10 + static_cast<int>(shm::ReadResult::kProducerStopped))
      << "10 + the ReadResult, 128 + a signal: " << controller;
}

TEST_F(SimHostProcess, InterruptShutsDownCleanlyWithTheLogFlushed) {
  const std::string log = testing::WriteTemp("", ".csv");
  Start({"--duration", "0", "--wait-controller", "0", "--log", log});
  ASSERT_TRUE(WaitSegment());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
  EXPECT_NE(Stderr().find("interrupted"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
  std::ifstream in(log);
  std::string header, line, last;
  int rows = 0;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("time,base_x", 0), 0u);
  while (std::getline(in, line)) {
    ++rows;
    last = line;
  }
  EXPECT_GT(rows, 10);
  EXPECT_EQ(std::count(last.begin(), last.end(), ','), std::count(header.begin(), header.end(), ','));
}

TEST_F(SimHostProcess, ContactParametersThatCannotWorkAreRefusedAtLoad) {
  scene_ = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  Start({"--contact", "soft", "--contact-stiffness", "-5"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("stiffness"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
  // a negative damping: the message says what would work (the implicit step takes any
  // damping >= 0; RK4's explicit stage evaluation refuses one too strong for its step)
  Start({"--contact", "soft", "--contact-damping", "-1"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("damping"), std::string::npos) << Stderr();
  Start({"--contact", "soft", "--contact-damping", "1e6", "--integrator", "rk4"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("damping"), std::string::npos) << Stderr();
}

TEST_F(SimHostProcess, SoftContactWithoutSolesIsAClearError) {
  Start({"--contact", "soft", "--wait-controller", "0", "--duration", "0.1"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("soles"), std::string::npos) << Stderr();
  // auto falls back to MuJoCo's contact for a model without soles
  Start({"--contact", "auto", "--wait-controller", "0", "--duration", "0.1"});
  EXPECT_EQ(Wait(), 0);
  EXPECT_NE(Stderr().find("native contact"), std::string::npos) << Stderr();
}

// the last logged value of a column of a sim_host data log
double LastLogged(const std::string& log, const std::string& column) {
  std::ifstream in(log);
  std::string header, line, last;
  std::getline(in, header);
  while (std::getline(in, line)) last = line;
  std::stringstream hs(header), ls(last);
  std::string name, value;
  while (std::getline(hs, name, ',') && std::getline(ls, value, ','))
    if (name == column) return std::stod(value);
  return std::nan("");
}

// A push on the base of the robot held in its initial pose: the impulse F dt sets the base
// moving forward, by less than the impulse over the mass since the sticking soles resist.
TEST_F(SimHostProcess, PushActsOnTheBaseOnlyWhileItLasts) {
  scene_ = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  const std::string quiet_log = testing::WriteTemp("", ".csv");
  const std::string pushed_log = testing::WriteTemp("", ".csv");
  Start({"--wait-controller", "0", "--duration", "0.3", "--log", quiet_log});
  ASSERT_EQ(Wait(), 0) << Stderr();
  // 150 N forward for 0.1 s at t = 0.2 s: the base moves forward, then settles
  Start({"--wait-controller", "0", "--duration", "0.3", "--log", pushed_log, "--push",
         "0.2,0.3,150,0,0,0,0,0"});
  ASSERT_EQ(Wait(), 0) << Stderr();
  const double quiet = LastLogged(quiet_log, "base_vx");
  const double pushed = LastLogged(pushed_log, "base_vx");
  // an impulse of 15 N s on 130.8 kg gives at most 0.115 m/s; the sticking soles take part
  EXPECT_GT(pushed - quiet, 0.02) << "quiet " << quiet << ", pushed " << pushed;
  EXPECT_LT(pushed - quiet, 0.115);
}

// A free box (2 kg, no gravity, a weightless motorised arm so the segment has a joint): a
// push's impulse is F times its window, exactly, since explicit Euler integrates a constant
// force exactly; overlapping pushes add and nothing stays in xfrc_applied after them.
constexpr const char* kFreeBox = R"(
<mujoco model="freebox">
  <option timestep="0.001" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="box">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1" mass="2" contype="0" conaffinity="0"/>
      <body name="arm">
        <joint name="j" type="hinge" axis="0 0 1" armature="1"/>
        <geom type="sphere" size="0.01" mass="1e-9" contype="0" conaffinity="0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="j" joint="j"/></actuator>
</mujoco>
)";

// the value of a column in the first row of a data log at or after `time`
double LoggedAt(const std::string& log, const std::string& column, double time) {
  std::ifstream in(log);
  std::string header, line;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream hs(header);
  for (std::string n; std::getline(hs, n, ',');) names.push_back(n);
  const size_t c = std::find(names.begin(), names.end(), column) - names.begin();
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> row;
    for (std::string v; std::getline(ls, v, ',');) row.push_back(std::stod(v));
    if (row.size() > c && row[0] >= time - 1e-9) return row[c];
  }
  return std::nan("");
}

TEST_F(SimHostProcess, PushImpulsesAreExactAndOverlappingPushesAdd) {
  scene_ = testing::WriteTemp(kFreeBox);
  const std::string log = testing::WriteTemp("", ".csv");
  // 10 N along x over [0.1, 0.3) s and 20 N along x plus 4 N along y over [0.2, 0.25) s
  Start({"--wait-controller", "0", "--contact", "native", "--duration", "0.5", "--log", log,
         "--push", "0.1,0.3,10,0,0,0,0,0", "--push", "0.2,0.25,20,4,0,0,0,0"});
  ASSERT_EQ(Wait(), 0) << Stderr();
  constexpr double kMass = 2 + 1e-9;  // [kg]
  constexpr double kTol = 1e-9;       // [m/s] round-off of 500 Euler steps
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.1), 0.0, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.2), 10 * 0.1 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.25), (10 * 0.15 + 20 * 0.05) / kMass, kTol);
  // after both windows: J = 10 x 0.2 + 20 x 0.05 = 3 N s along x, 4 x 0.05 = 0.2 N s along y,
  // and the velocity stays there (no wrench left behind)
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.3), 3.0 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vx", 0.5), 3.0 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vy", 0.5), 0.2 / kMass, kTol);
  EXPECT_NEAR(LoggedAt(log, "base_vz", 0.5), 0.0, kTol);
}

TEST_F(SimHostProcess, BadPushesAreRefusedBeforeTheSegmentExists) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"0.3,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},   // the window ends before it starts
      {"0.2,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},   // empty window
      {"-1,0.2,1,0,0,0,0,0", "0 <= t0 < t1"},    // before the start
      {"0.1,0.2,1,0,0", "5 values, expected 8"},  // too few
      {"0.1,0.2,1,0,0,0,0,0,0", "more than 8"},  // too many
      {"0.1,0.2,inf,0,0,0,0,0", "not finite"},
      {"0.1,0.2,nan,0,0,0,0,0", "not finite"},
      {"0.1,0.2,1x,0,0,0,0,0", "not a number"},
      {"0.1,,1,0,0,0,0,0", "not a number"}};
  for (const auto& [spec, message] : cases) {
    Start({"--wait-controller", "0", "--duration", "0.1", "--push", "0.1,0.2,1,0,0,0,0,0", "--push", spec});
    EXPECT_EQ(Wait(), 2) << spec;
    EXPECT_NE(Stderr().find(message), std::string::npos) << spec << ": " << Stderr();
    EXPECT_NE(Stderr().find("t0,t1,fx,fy,fz,tx,ty,tz"), std::string::npos) << Stderr();
    EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_))) << spec;
  }
  // the arm has no free base to push
  Start({"--wait-controller", "0", "--duration", "0.1", "--push", "0.1,0.2,1,0,0,0,0,0"});
  EXPECT_EQ(Wait(), 2);
  EXPECT_NE(Stderr().find("no free joint"), std::string::npos) << Stderr();
  EXPECT_FALSE(fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_)));
}

TEST_F(SimHostProcess, RealTimeModePacesToTheWallClock) {
  const std::string summary = testing::WriteTemp("", ".json");
  const auto t0 = Clock::now();
  Start({"--duration", "1", "--wait-controller", "0", "--realtime", "--summary", summary});
  EXPECT_EQ(Wait(), 0);
  const double wall = Since(t0);
  EXPECT_GT(wall, 0.99);  // lock-step would take a few milliseconds for this model
  EXPECT_LT(wall, 1.5);
  std::ifstream in(summary);
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_NE(ss.str().find("\"mode\": \"realtime\""), std::string::npos) << ss.str();
}

TEST_F(SimHostProcess, NoControllerWithinTheWaitIsAClearError) {
  Start({"--duration", "1", "--wait-controller", "0.2"});
  EXPECT_EQ(Wait(), 5);
  EXPECT_NE(Stderr().find("no controller attached"), std::string::npos) << Stderr();
}

TEST_F(SimHostProcess, RealTimeFactorLeavesOutTheWaitForANewController) {
  const std::string summary = testing::WriteTemp("", ".json");
  Start({"--duration", "0", "--realtime", "--on-controller-loss", "wait", "--summary", summary});
  ASSERT_TRUE(WaitSegment());
  ASSERT_EQ(RunDyingController(), 0);
  // a second of waiting for a new controller, simulated time frozen
  const auto t0 = Clock::now();
  while (Stderr().find("waiting for a new controller") == std::string::npos && Since(t0) < 2)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  std::this_thread::sleep_for(std::chrono::seconds(1));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(summary));
  const double wall = j["wall_time"], waiting = j["wall_waiting"], sim = j["sim_time"];
  EXPECT_GT(waiting, 0.9);
  EXPECT_LT(waiting, wall);
  EXPECT_NEAR(j["real_time_factor"].get<double>(), sim / (wall - waiting), 1e-9);
  EXPECT_NE(Stderr().find("of it waiting for a controller"), std::string::npos) << Stderr();
}

TEST_F(SimHostProcess, ProgressOfARunWithoutAnEndSaysSo) {
  progress_ = "0.05";
  Start({"--duration", "0", "--wait-controller", "0", "--realtime"});
  ASSERT_TRUE(WaitSegment());
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  kill(pid_, SIGINT);
  EXPECT_EQ(Wait(), 130);
  const std::string e = Stderr();
  EXPECT_NE(e.find("s simulated (until stopped)"), std::string::npos) << e;
  EXPECT_EQ(e.find(" of 0.00 s"), std::string::npos) << e;
}

}  // namespace
}  // namespace ohrp::sim
