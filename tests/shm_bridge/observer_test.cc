// Tests the observer (read-only end): it attaches without claiming the controller slot, many
// at once, never writes a byte of the segment, sees every published block through the seqlock
// (or the newest when it is slower), the controller's last commands, and the producer's end.
#include "shm_bridge/observer.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "shm_bridge/bridge.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::RawSegment;
using testing::Spawn;
using testing::WaitExit;
using testing::WaitFor;

class ObserverTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = testing::UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    testing::RemoveSegment(name_);
    Status status;
    producer_ = Producer::Create(testing::SmallConfig(name_), &status);
    ASSERT_TRUE(status.ok()) << status.message;
  }
  void TearDown() override {
    producer_.reset();
    testing::RemoveSegment(name_);
  }

  void Publish(uint64_t k) {
    SensorBlock& s = producer_->BeginSensors();
    s.cycle = k;
    s.time = 0.005 * static_cast<double>(k);
    for (int j = 0; j < 3; ++j) s.q[j] = 100.0 * static_cast<double>(k) + j;
    producer_->PublishSensors();
  }

  std::string name_;
  std::unique_ptr<Producer> producer_;
};

TEST_F(ObserverTest, OpenReportsAMissingSegment) {
  Observer o;
  const Status s = o.open(name_ + "_none");
  EXPECT_EQ(s.code, Error::kNoSegment);
  EXPECT_NE(s.message.find("is sim_host or hw_driver running"), std::string::npos) << s.message;
}

TEST_F(ObserverTest, ManyObserversLeaveTheControllerSlotFree) {
  Observer a, b, c;
  ASSERT_TRUE(a.open(name_).ok());
  ASSERT_TRUE(b.open(name_).ok());
  ASSERT_TRUE(c.open(name_).ok());
  EXPECT_EQ(producer_->controller_pid(), 0);
  EXPECT_STREQ(a.header().joint_names[1], "knee");
  EXPECT_EQ(a.header().njoint, 3);
  // a controller still attaches
  RobotAdaptor controller;
  EXPECT_TRUE(controller.open(name_).ok());
  EXPECT_EQ(a.controller_pid(), getpid());
}

TEST_F(ObserverTest, NeverWritesTheSegment) {
  Publish(0);
  RawSegment raw(name_);
  std::vector<char> before(sizeof(Segment));
  std::memcpy(before.data(), raw.get(), sizeof(Segment));
  {
    Observer o;
    ASSERT_TRUE(o.open(name_).ok());
    SensorBlock s{};
    EXPECT_EQ(o.read(&s, 0.1), ReadResult::kOk);
    EXPECT_EQ(o.read(&s, 0.01), ReadResult::kTimeout);
    CommandBlock c{};
    EXPECT_FALSE(o.commands(&c));  // nothing written yet
  }
  EXPECT_EQ(std::memcmp(before.data(), raw.get(), sizeof(Segment)), 0);
}

TEST_F(ObserverTest, ReadsEachNewBlockOnceAndTheNewestWhenBehind) {
  Observer o;
  ASSERT_TRUE(o.open(name_).ok());
  SensorBlock s{};
  EXPECT_EQ(o.read(&s, 0.02), ReadResult::kTimeout);  // nothing published yet
  Publish(0);
  ASSERT_EQ(o.read(&s, 0.1), ReadResult::kOk);
  EXPECT_EQ(s.cycle, 0u);
  EXPECT_EQ(o.read(&s, 0.02), ReadResult::kTimeout);  // the same block is not returned twice
  Publish(1);
  Publish(2);
  Publish(3);
  ASSERT_EQ(o.read(&s, 0.1), ReadResult::kOk);
  EXPECT_EQ(s.cycle, 3u);  // slower than the producer: the newest, the counter tells the gap
  EXPECT_EQ(s.q[2], 302.0);
}

TEST_F(ObserverTest, SeesBlocksPublishedByAnotherProcessUntorn) {
  constexpr uint64_t kCycles = 3000;
  Observer o;
  ASSERT_TRUE(o.open(name_).ok());
  const pid_t child = Spawn([&] {
    // the observer in a child: every block it sees is consistent, cycles only increase
    uint64_t last = 0, seen = 0;
    SensorBlock s{};
    for (;;) {
      const ReadResult r = o.read(&s, 2.0);
      if (r == ReadResult::kProducerStopped) break;
      if (r != ReadResult::kOk) return 2;
      for (int j = 0; j < 3; ++j) {
        if (s.q[j] != 100.0 * static_cast<double>(s.cycle) + j) return 3;  // torn
      }
      if (seen > 0 && s.cycle <= last) return 4;
      last = s.cycle;
      ++seen;
    }
    return last == kCycles - 1 && seen > 10 ? 0 : 5;
  });
  for (uint64_t k = 0; k < kCycles; ++k) {
    Publish(k);
    if (k % 10 == 0) usleep(100);  // ~30 ms in all: the observer sees many of them
  }
  usleep(20000);  // the observer polls every 0.5 ms: let it see the last block
  producer_->SetState(ProducerState::kStopped);
  EXPECT_EQ(WaitExit(child, 10.0), 0);
}

TEST_F(ObserverTest, SeesTheControllersLastCommands) {
  Observer o;
  ASSERT_TRUE(o.open(name_).ok());
  RobotAdaptor controller;
  ASSERT_TRUE(controller.open(name_).ok());
  Publish(4);
  SensorBlock s{};
  ASSERT_EQ(controller.read(&s), ReadResult::kOk);
  CommandBlock c{};
  c.njoint = 3;
  c.joint[1].mode = JointMode::kPosition;
  c.joint[1].q_ref = -0.5;
  c.joint[1].kp = 250.0;
  ASSERT_EQ(controller.write(c), ReadResult::kOk);
  CommandBlock seen{};
  ASSERT_TRUE(o.commands(&seen));
  EXPECT_EQ(seen.answers_cycle, 4u);
  EXPECT_EQ(seen.njoint, 3);
  EXPECT_EQ(seen.joint[1].q_ref, -0.5);
  EXPECT_EQ(seen.joint[1].kp, 250.0);
}

// the controller's guard record (issue 29) travels with the commands (copied with the block's
// head, as the producer's WaitCommands copies it); a name filling its whole field arrives cut
// and terminated
TEST_F(ObserverTest, SeesTheGuardRecordWithTheCommands) {
  Observer o;
  ASSERT_TRUE(o.open(name_).ok());
  RobotAdaptor controller;
  ASSERT_TRUE(controller.open(name_).ok());
  Publish(2);
  SensorBlock s{};
  ASSERT_EQ(controller.read(&s), ReadResult::kOk);
  CommandBlock c{};
  c.njoint = 3;
  c.guard.holding = 1;
  c.guard.holds = 3;
  c.guard.distance = 0.0017;
  std::snprintf(c.guard.link_a, kNameLen, "%s", "WAIST_R");
  std::memset(c.guard.link_b, 'X', kNameLen);  // no terminator
  ASSERT_EQ(controller.write(c), ReadResult::kOk);
  CommandBlock seen{};
  ASSERT_TRUE(o.commands(&seen));
  EXPECT_EQ(seen.guard.holding, 1u);
  EXPECT_EQ(seen.guard.holds, 3u);
  EXPECT_EQ(seen.guard.distance, 0.0017);
  EXPECT_STREQ(seen.guard.link_a, "WAIST_R");
  EXPECT_EQ(std::string(seen.guard.link_b), std::string(kNameLen - 1, 'X'));
}

TEST_F(ObserverTest, ReportsTheProducersEnd) {
  Observer o;
  ASSERT_TRUE(o.open(name_).ok());
  Publish(0);
  producer_->SetState(ProducerState::kFailed);
  SensorBlock s{};
  EXPECT_EQ(o.read(&s, 0.1), ReadResult::kOk);  // the last block is still returned once
  EXPECT_EQ(o.read(&s, 0.1), ReadResult::kProducerStopped);
  EXPECT_EQ(o.producer_state(), ProducerState::kFailed);
}

TEST_F(ObserverTest, ReportsADeadProducer) {
  const std::string other = name_ + "_dead";
  testing::RemoveSegment(other);
  Observer o;
  testing::Pipe opened;
  const pid_t child = Spawn([&] {
    Status status;
    auto p = Producer::Create(testing::SmallConfig(other), &status);
    if (!status.ok()) return 1;
    opened.Send();
    pause();  // killed below, leaving its segment behind
    return 0;
  });
  ASSERT_TRUE(opened.Receive());
  ASSERT_TRUE(o.open(other).ok());
  kill(child, SIGKILL);
  EXPECT_EQ(WaitExit(child), 128 + SIGKILL);
  SensorBlock s{};
  EXPECT_EQ(o.read(&s, 1.0), ReadResult::kProducerGone);
  o.close();
  testing::RemoveSegment(other);
}

}  // namespace
}  // namespace ohrp::shm
