// The segment's guards with the built programs (bridge.h: "What another process can do to the
// segment"): sim_host and the posture controller whose segment file is truncated under them end
// with their documented exit code (5) and a message, not SIGBUS; posture whose producer ends
// over a corrupted commands_ready word exits non-zero in every trial (before: 0 in most).
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <string>
#include <thread>

#include "common/process.h"
#include "common/scratch.h"
#include "fake_robot.h"  // tests/controllers: the fake robot, the programs, SampleRobotJoints
#include "test_models.h"  // tests/sim_host: the two-joint arm
#include "test_util.h"

namespace ohrp::shm {
namespace {

namespace ctl = ohrp::controllers::testing;
using testing::DevShmPath;
using testing::RawSegment;
using testing::RemoveSegment;
using testing::UniqueSegment;

constexpr int kExitSegmentCorrupted = 5;  // sim_host's and the controllers' documented code
constexpr int kSigbus = 128 + SIGBUS;

bool Exists(const std::string& name) { return access(DevShmPath(name).c_str(), F_OK) == 0; }

class SegmentProcessTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    RemoveSegment(name_);
    log_ = ohrp::testing::ScratchPath("program", ".log");
  }
  void TearDown() override {
    ohrp::testing::Kill(&producer_);
    ohrp::testing::Kill(&controller_);
    RemoveSegment(name_);
  }
  std::string name_, log_;
  pid_t producer_ = -1, controller_ = -1;
};

// sim_host (the arm) and a controller cycling; the file truncated to nothing: sim_host exits 5
// saying "truncated", the controller's read or write returns kSegmentCorrupted, the segment
// is removed; before, both died of SIGBUS without a word.
TEST_F(SegmentProcessTest, SimHostAndItsControllerEndWithAMessageWhenTheFileIsTruncated) {
  const std::string scene = sim::testing::WriteTemp(sim::testing::kTwoJointArm);
  producer_ = ohrp::testing::Spawn(
      {std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", scene, "--segment", name_,
       "--physics-dt", "0.001", "--control-period", "0.002", "--duration", "0"},
      {.err = log_});
  ohrp::testing::Pipe cycling;
  controller_ = ohrp::testing::Spawn([&]() -> int {
    RobotAdaptor a;
    if (!testing::OpenWhenReady(&a, name_, {}, 10.0).ok()) return 3;
    SensorBlock s{};
    for (int cycle = 0;; ++cycle) {
      ReadResult r = a.read(&s);
      if (r == ReadResult::kOk) {
        CommandBlock c{};
        c.njoint = 2;
        for (int j = 0; j < 2; ++j) {
          c.joint[j].mode = JointMode::kPosition;
          c.joint[j].q_ref = s.q[j];
          c.joint[j].kp = 10.0;
          c.joint[j].kd = 1.0;
        }
        r = a.write(c);
      }
      if (r != ReadResult::kOk) return 10 + static_cast<int>(r);
      if (cycle == 50) cycling.Send();
    }
  });
  ASSERT_TRUE(cycling.Receive(20.0)) << ohrp::testing::ReadFile(log_);
  ASSERT_EQ(truncate(DevShmPath(name_).c_str(), 0), 0);
  const int sim_host = ohrp::testing::WaitExit(&producer_, 10.0);
  const int controller = ohrp::testing::WaitExit(&controller_, 10.0);
  const std::string err = ohrp::testing::ReadFile(log_);
  EXPECT_EQ(sim_host, kExitSegmentCorrupted) << "135: SIGBUS\n" << err;
  EXPECT_NE(err.find("segment's file was truncated"), std::string::npos) << err;
  EXPECT_EQ(controller, 10 + static_cast<int>(ReadResult::kSegmentCorrupted)) << "135: SIGBUS";
  EXPECT_FALSE(Exists(name_));
}

// posture attached to a fake robot (a producer in this test process, which the truncation
// reaches too): posture exits 5 naming the truncation; the producer's check says kTruncated.
TEST_F(SegmentProcessTest, PostureEndsWithAMessageWhenTheFileIsTruncated) {
  ctl::FakeRobotSpec spec;
  spec.segment = name_;
  spec.joints = ctl::SampleRobotJoints();
  std::string error;
  auto robot = ctl::FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  controller_ = ctl::Spawn({ctl::Program("posture"), "--segment", name_, "--ramp", "0.5",
                            "--attach-timeout", "5"},
                           log_);
  ASSERT_TRUE(robot->RunUntilCommands(20)) << ohrp::testing::ReadFile(log_);
  ASSERT_EQ(truncate(DevShmPath(name_).c_str(), 0), 0);
  const int posture = robot->RunUntilExit(controller_, 10.0);  // cycles: faults here too
  controller_ = -1;
  const std::string log = ohrp::testing::ReadFile(log_);
  EXPECT_EQ(posture, kExitSegmentCorrupted) << kSigbus << ": SIGBUS\n" << log;
  EXPECT_NE(log.find("truncated"), std::string::npos) << log;
}

// A producer in this process that cycles as sim_host does (1 ms of "physics" per cycle) and,
// once it finds its segment faulty, ends its run (kStopped, asked) and removes the segment.
// Returns the fault it found (kNone: posture left first).
SegmentFault RunProducerUntilFault(const std::string& name, pid_t posture,
                                   std::atomic<bool>* cycling) {
  ProducerConfig config;
  config.segment_name = name;
  config.robot_name = "SampleRobot";
  config.joint_names = ctl::SampleRobotJoints();
  config.default_kp.assign(config.joint_names.size(), 100.0);
  config.default_kd.assign(config.joint_names.size(), 2.0);
  config.physics_period = config.control_period = 0.005;
  Status status;
  auto producer = Producer::Create(config, &status);
  if (producer == nullptr) return SegmentFault::kNone;
  int answered = 0;
  const double t_end = MonotonicSeconds() + 10.0;
  for (uint64_t cycle = 0; MonotonicSeconds() < t_end; ++cycle) {
    if (producer->sync_corrupted()) break;
    SensorBlock& s = producer->BeginSensors();
    s.cycle = cycle;
    s.time = 0.005 * static_cast<double>(cycle);
    producer->PublishSensors();
    CommandBlock cmd{};
    const WaitResult r = producer->WaitCommands(2.0, &cmd);
    if (producer->sync_corrupted()) break;
    if (r == WaitResult::kCommands && ++answered == 20) cycling->store(true);
    if (r == WaitResult::kNoController || r == WaitResult::kControllerDied) {
      if (answered > 0 || !ohrp::testing::Running(posture)) break;
      usleep(1000);
      continue;
    }
    usleep(1000);  // the physics steps
  }
  const SegmentFault fault = producer->fault();
  producer->SetState(ProducerState::kStopped);
  return fault;
}

// commands_ready overwritten while posture runs against a producer that ends its run when it
// finds the word: posture exits non-zero (5) in every trial, never 0 (before: 0 whenever the
// producer found the word first, 9 of 15 trials against sim_host).
TEST_F(SegmentProcessTest, PostureExitsNonZeroInEveryTrialAfterACorruptedCommandsReadyWord) {
  std::mt19937 random(28);
  constexpr int kTrials = 6;
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    RemoveSegment(name_);
    controller_ = ctl::Spawn({ctl::Program("posture"), "--segment", name_, "--ramp", "0.5",
                              "--attach-timeout", "5"},
                             log_);
    std::atomic<bool> cycling{false};
    std::thread scribbler([&] {
      while (!cycling.load()) usleep(1000);
      usleep(static_cast<useconds_t>(random() % 6000));
      RawSegment raw(name_);
      std::atomic_ref<uint32_t>(raw.get()->sync.commands_ready.word).store(0xdeadbeefu);
    });
    const SegmentFault found = RunProducerUntilFault(name_, controller_, &cycling);
    scribbler.join();
    const int posture = ohrp::testing::WaitExit(&controller_, 10.0);
    EXPECT_EQ(posture, kExitSegmentCorrupted) << ohrp::testing::ReadFile(log_);
    EXPECT_EQ(found, SegmentFault::kWakeUpWords);
  }
  const std::string log = ohrp::testing::ReadFile(log_);
  EXPECT_NE(log.find("wake-up words are corrupted"), std::string::npos) << log;
}

}  // namespace
}  // namespace ohrp::shm
