// Tests how the runner (controllers/runner.h) ends a run, across real processes: producer
// killed, producer ended normally, producer stalled, controller dropped by the producer,
// segment late or missing.
#include "controllers/runner.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

using testing::FakeRobot;
using testing::FakeRobotSpec;

class RunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = testing::UniqueSegment("runner");
    testing::RemoveSegment(segment_);
    log_ = testing::TempPath("runner_log");
    spec_.segment = segment_;
    spec_.joints = testing::SampleRobotJoints();
  }
  void TearDown() override {
    testing::RemoveSegment(segment_);
    std::remove(log_.c_str());
  }
  pid_t SpawnPosture(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {testing::Program("posture"), "--segment", segment_,
                                     "--ramp", "0.1"};
    args.insert(args.end(), extra.begin(), extra.end());
    return testing::Spawn(args, log_);
  }
  std::string segment_, log_;
  FakeRobotSpec spec_;
};

TEST_F(RunnerTest, ExitsNonZeroNamingThePidWhenTheProducerIsKilled) {
  ohrp::testing::Pipe ready;
  const pid_t producer = ohrp::testing::Spawn([&]() -> int {
    // the fake robot, in its own process, cycling until killed
    std::string error;
    auto robot = FakeRobot::Create(spec_, &error);
    if (!robot) _exit(1);
    bool told = false;
    while (true) {
      robot->Cycle(0.5);
      if (!told && robot->records().size() >= 20) told = ready.Send();
    }
  });
  ASSERT_GE(producer, 0);
  pid_t controller = SpawnPosture({"--attach-timeout", "5"});
  ASSERT_TRUE(ready.Receive(10.0)) << testing::ReadFile(log_);  // 20 commands exchanged
  ohrp::testing::Kill(producer);  // reaped: no zombie that would still look alive

  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(testing::WaitExit(controller, 10.0), kExitProducerLost);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(took, 1.5);  // noticed within a slice, not at the end of the read timeout
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("sim_host (pid " + std::to_string(producer) + ") is gone"),
            std::string::npos)
      << log;
}

TEST_F(RunnerTest, ExitsZeroWhenTheProducerEndsNormally) {
  std::string error;
  auto robot = FakeRobot::Create(spec_, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = SpawnPosture();
  ASSERT_TRUE(robot->RunUntilCommands(20)) << testing::ReadFile(log_);
  robot->Stop();
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitOk) << testing::ReadFile(log_);
  EXPECT_NE(testing::ReadFile(log_).find("ended its run"), std::string::npos);
}

TEST_F(RunnerTest, ExitsNonZeroWhenTheProducerStallsPastTheReadTimeout) {
  std::string error;
  auto robot = FakeRobot::Create(spec_, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = SpawnPosture({"--read-timeout", "0.3"});
  ASSERT_TRUE(robot->RunUntilCommands(10)) << testing::ReadFile(log_);
  // the producer stays alive but publishes nothing more
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitProducerLost);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("alive but not cycling"), std::string::npos) << log;
}

// stopped (SIGSTOP) past the producer's timeout, the controller is dropped; resumed, it must
// not carry on nor report a normal end
TEST_F(RunnerTest, ExitsSevenWhenTheProducerDroppedItWhileItWasStopped) {
  std::string error;
  auto robot = FakeRobot::Create(spec_, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = SpawnPosture();
  ASSERT_TRUE(robot->RunUntilCommands(10)) << testing::ReadFile(log_);
  kill(pid, SIGSTOP);
  ASSERT_TRUE(robot->DropController(pid));
  kill(pid, SIGCONT);
  EXPECT_EQ(robot->RunUntilExit(pid), kExitDropped) << testing::ReadFile(log_);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("dropped this controller"), std::string::npos) << log;
  EXPECT_EQ(robot->controller_pid(), 0);  // it released nothing that was not its own
  robot->Stop();
}

TEST_F(RunnerTest, AttachTimeoutWaitsForALateProducer) {
  pid_t pid = SpawnPosture({"--attach-timeout", "10"});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::string error;
  auto robot = FakeRobot::Create(spec_, &error);
  ASSERT_TRUE(robot) << error;
  ASSERT_TRUE(robot->RunUntilCommands(10)) << testing::ReadFile(log_);
  robot->Stop();
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitOk) << testing::ReadFile(log_);
}

TEST_F(RunnerTest, WithoutAttachTimeoutAMissingSegmentFailsAtOnce) {
  pid_t pid = SpawnPosture();
  EXPECT_EQ(testing::WaitExit(pid, 5.0), kExitAttach);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("cannot attach to segment '" + segment_ + "'"), std::string::npos) << log;
  EXPECT_NE(log.find("--attach-timeout"), std::string::npos) << log;
}

TEST_F(RunnerTest, SigtermFreesTheSlotForTheNextController) {
  std::string error;
  auto robot = FakeRobot::Create(spec_, &error);
  ASSERT_TRUE(robot) << error;
  pid_t first = SpawnPosture();
  ASSERT_TRUE(robot->RunUntilCommands(10)) << testing::ReadFile(log_);
  EXPECT_EQ(robot->controller_pid(), first);
  kill(first, SIGTERM);
  EXPECT_EQ(robot->RunUntilExit(first), kExitOk) << testing::ReadFile(log_);
  EXPECT_EQ(robot->controller_pid(), 0);
  pid_t second = SpawnPosture();
  ASSERT_TRUE(robot->RunUntilCommands(10)) << testing::ReadFile(log_);
  EXPECT_EQ(robot->controller_pid(), second);
  robot->Stop();
  EXPECT_EQ(testing::WaitExit(second, 10.0), kExitOk) << testing::ReadFile(log_);
}

}  // namespace
}  // namespace ohrp::controllers
