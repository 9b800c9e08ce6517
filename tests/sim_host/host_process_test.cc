// Tests sim_host as a process, with the real binary: what it refuses at load (a malformed or
// missing model, contact parameters that cannot work), lock-step timing and command checks, and
// real-time pacing with its progress and real-time factor. The faults are in
// host_faults_test.cc, the pushes in host_pushes_test.cc (the fixture: host_process.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "host_process.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using testing::Clock;
using testing::SimHostProcess;
using testing::Since;

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
