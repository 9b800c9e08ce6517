// Tests the robot adaptor's cycle across real processes: the lock-step ping-pong with data
// checks, a late controller answering the pending cycle, read's results when nothing comes or
// the producer dies, and both ends facing wake-up words that another process scribbles on.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <thread>

#include "adaptor_fixture.h"
#include "shm_bridge/bridge.h"

namespace ohrp::shm {
namespace {

using testing::AdaptorTest;
using testing::CommandValue;
using testing::OpenWhenReady;
using testing::Pipe;
using testing::RawSegment;
using testing::SensorValue;
using testing::Spawn;
using testing::WaitExit;
using testing::WaitFor;

//---------------- the cycle ----------------

TEST_F(AdaptorTest, PingPongKeepsEveryCycleIntact) {
  constexpr uint64_t kCycles = 2000;
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    SensorBlock s{};
    CommandBlock c{};
    for (uint64_t k = 0; k < kCycles; ++k) {
      if (adaptor.read(&s) != ReadResult::kOk) return 2;
      if (s.cycle != k) return 3;
      for (int j = 0; j < 3; ++j) {
        if (s.q[j] != SensorValue(k, j) || s.tau[j] != -s.q[j]) return 4;
      }
      if (s.seq % 2 != 0) return 5;
      c.njoint = 3;
      for (int j = 0; j < 3; ++j) {
        c.joint[j].mode = JointMode::kPosition;
        c.joint[j].q_ref = CommandValue(k, j);
        c.joint[j].kp = static_cast<double>(k);
      }
      c.answers_cycle = 12345;  // set by the bridge, whatever the caller puts here
      if (adaptor.write(c) != ReadResult::kOk) return 6;
    }
    return adaptor.read(&s) == ReadResult::kProducerStopped ? 0 : 7;
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));

  int bad = 0;
  for (uint64_t k = 0; k < kCycles && bad < 5; ++k) {
    SensorBlock& s = producer->BeginSensors();
    s.cycle = k;
    s.time = 0.005 * static_cast<double>(k);
    for (int j = 0; j < 3; ++j) {
      s.q[j] = SensorValue(k, j);
      s.tau[j] = -s.q[j];
    }
    producer->PublishSensors();
    CommandBlock c{};
    const WaitResult r = producer->WaitCommands(2.0, &c);
    bool ok = r == WaitResult::kCommands && c.answers_cycle == k && c.njoint == 3;
    for (int j = 0; ok && j < 3; ++j) {
      ok = c.joint[j].mode == JointMode::kPosition && c.joint[j].q_ref == CommandValue(k, j) &&
           c.joint[j].kp == static_cast<double>(k);
    }
    if (!ok) {
      ++bad;
      ADD_FAILURE() << "cycle " << k << ": result " << static_cast<int>(r) << " answers_cycle "
                    << c.answers_cycle;
    }
  }
  producer.reset();  // the child's last read sees kProducerStopped
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(AdaptorTest, LateControllerAnswersThePendingCycle) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  SensorBlock& s = producer->BeginSensors();
  s.cycle = 7;
  s.q[0] = 7.5;
  producer->PublishSensors();
  CommandBlock out{};
  ASSERT_EQ(producer->WaitCommands(1.0, &out), WaitResult::kNoController);

  Pipe done;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    AdaptorOptions options;
    options.read_timeout = 0.5;
    if (!adaptor.open(name_, options).ok()) return 1;
    SensorBlock in{};
    if (adaptor.read(&in) != ReadResult::kOk) return 2;  // the pending cycle, no new publish
    if (in.cycle != 7 || in.q[0] != 7.5) return 3;
    CommandBlock c{};
    c.njoint = 3;
    c.joint[0].tau_ff = 2.5;
    adaptor.write(c);
    return done.Receive() ? 0 : 4;  // stays attached until the producer has the answer
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));
  EXPECT_EQ(producer->WaitCommands(2.0, &out), WaitResult::kCommands);
  EXPECT_EQ(out.answers_cycle, 7u);
  EXPECT_EQ(out.joint[0].tau_ff, 2.5);
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(AdaptorTest, ReadTimesOutWhenNothingIsPublished) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  AdaptorOptions options;
  options.read_timeout = 0.1;
  options.slice = 0.02;
  ASSERT_TRUE(adaptor.open(name_, options).ok());
  SensorBlock s{};
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(adaptor.read(&s), ReadResult::kTimeout);
  const double waited = MonotonicSeconds() - t0;
  EXPECT_GE(waited, 0.095);
  EXPECT_LT(waited, 0.5);
}

TEST_F(AdaptorTest, ReadReturnsProducerGoneSoonAfterTheProducerIsKilled) {
  Pipe created;
  const pid_t child = Spawn([&] {
    auto p = Create();
    if (p == nullptr) return 1;
    created.Send();
    SensorBlock& s = p->BeginSensors();
    s.cycle = 0;
    p->PublishSensors();
    CommandBlock c{};
    while (p->WaitCommands(10.0, &c) != WaitResult::kCommands) {
    }
    pause();  // waits to be killed, never publishes cycle 1
    return 2;
  });
  ASSERT_TRUE(created.Receive());
  RobotAdaptor adaptor;
  AdaptorOptions options;
  options.read_timeout = 2.0;
  options.slice = 0.02;
  ASSERT_TRUE(adaptor.open(name_, options).ok());
  SensorBlock s{};
  ASSERT_EQ(adaptor.read(&s), ReadResult::kOk);
  ASSERT_EQ(adaptor.write(CommandBlock{}), ReadResult::kOk);

  // kill the producer while this process is blocked in read, and reap it at once
  double killed_at = 0.0;
  int exit_code = 0;
  std::thread killer([&] {
    usleep(50000);
    killed_at = MonotonicSeconds();
    kill(child, SIGKILL);
    exit_code = WaitExit(child);
  });
  const ReadResult r = adaptor.read(&s);
  const double returned_at = MonotonicSeconds();
  killer.join();
  EXPECT_EQ(exit_code, 128 + SIGKILL);
  EXPECT_EQ(r, ReadResult::kProducerGone) << ReadResultName(r);
  EXPECT_LT(returned_at - killed_at, 0.2);
  EXPECT_GT(returned_at - killed_at, 0.0);
}

//---------------- corrupted wake-up words ----------------

TEST_F(AdaptorTest, OpenRefusesCorruptedWakeUpWords) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  raw.get()->sync.sensors_ready.word = 0xdeadbeef;
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kInvalidHeader);
  EXPECT_TRUE(Contains(s.message, "corrupted wake-up words")) << s.message;
  EXPECT_TRUE(Contains(s.message, "restart the producer")) << s.message;
  EXPECT_FALSE(adaptor.is_open());
}

// Another process scribbles random bytes on the wake-up words while a producer and a
// controller cycle: both ends stop with a clear result within a short time; none aborts
// (glibc's "The futex facility returned an unexpected error code" with the old semaphores),
// none hangs or spins for ever.
TEST_F(AdaptorTest, ScribbledWakeUpWordsEndBothEndsWithAClearResult) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    SensorBlock s{};
    CommandBlock c{};
    c.njoint = 3;
    for (;;) {
      ReadResult r = adaptor.read(&s);
      if (r == ReadResult::kOk) r = adaptor.write(c);
      if (r != ReadResult::kOk) return 10 + static_cast<int>(r);
    }
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));

  // a few clean cycles, then the scribbler starts
  CommandBlock out{};
  uint64_t k = 0;
  for (; k < 100; ++k) {
    producer->BeginSensors().cycle = k;
    producer->PublishSensors();
    ASSERT_EQ(producer->WaitCommands(2.0, &out), WaitResult::kCommands);
  }
  std::atomic<bool> stop{false};
  std::thread scribbler([&] {
    RawSegment raw(name_);
    std::mt19937 random(11);
    auto* bytes = reinterpret_cast<unsigned char*>(&raw.get()->sync);
    while (!stop.load()) {
      for (std::size_t i = 0; i < sizeof(Sync); ++i) bytes[i] = static_cast<unsigned char>(random());
      usleep(500);
    }
  });
  const double t0 = MonotonicSeconds();
  while (!producer->sync_corrupted() && MonotonicSeconds() - t0 < 5.0) {
    producer->BeginSensors().cycle = ++k;
    producer->PublishSensors();
    producer->WaitCommands(0.5, &out);
  }
  const double producer_noticed = MonotonicSeconds() - t0;
  const int code = WaitExit(child, 5.0);
  const double controller_noticed = MonotonicSeconds() - t0;
  stop = true;
  scribbler.join();

  EXPECT_TRUE(producer->sync_corrupted());
  EXPECT_LT(producer_noticed, 1.0);
  EXPECT_EQ(code, 10 + static_cast<int>(ReadResult::kSyncCorrupted))
      << "10 + the ReadResult; 128 + a signal when killed (134: aborted); -1: hung";
  EXPECT_LT(controller_noticed, 1.0);
  EXPECT_NE(std::string(ReadResultName(ReadResult::kSyncCorrupted)).find("corrupted"),
            std::string::npos);
}

// the race of a controller one cycle behind: the producer publishes cycle k and posts, the
// controller wakes, the producer publishes k+1 and posts again before the copy, the controller
// copies k+1; the second post then announces a block already returned. Republishing the same
// cycle makes that post without the race: the read must wait for the next cycle, not return
// the same block twice (a controller would see its sensors' time stop: stale sensors)
TEST_F(AdaptorTest, ACycleIsReturnedOnceEvenWhenItsWakeUpComesTwice) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  AdaptorOptions options;
  options.read_timeout = 0.1;
  options.slice = 0.02;
  ASSERT_TRUE(adaptor.open(name_, options).ok());
  const auto publish = [&](uint64_t cycle) {
    SensorBlock& s = producer->BeginSensors();
    s.cycle = cycle;
    s.time = 0.001 * static_cast<double>(cycle);
    producer->PublishSensors();
  };
  SensorBlock in{};
  publish(5);
  ASSERT_EQ(adaptor.read(&in), ReadResult::kOk);
  EXPECT_EQ(in.cycle, 5u);
  publish(5);  // the second wake-up for cycle 5
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(adaptor.read(&in), ReadResult::kTimeout);
  EXPECT_GE(MonotonicSeconds() - t0, 0.095);
  publish(6);
  ASSERT_EQ(adaptor.read(&in), ReadResult::kOk);
  EXPECT_EQ(in.cycle, 6u);
  EXPECT_DOUBLE_EQ(in.time, 0.006);
}

// A paused producer (sim_host's control channel) republishes its last cycle with
// status::kPaused as a heartbeat: each one restarts the read's timeout, so a pause of 0.6 s
// outlives a 0.2 s --read-timeout; the next cycle is then returned, and once the heartbeats
// stop the read times out again
TEST_F(AdaptorTest, APausedProducersHeartbeatKeepsTheReadWaiting) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  AdaptorOptions options;
  options.read_timeout = 0.2;
  options.slice = 0.02;
  ASSERT_TRUE(adaptor.open(name_, options).ok());
  const auto publish = [&](uint64_t cycle, uint32_t status) {
    SensorBlock& s = producer->BeginSensors();
    s.cycle = cycle;
    s.time = 0.001 * static_cast<double>(cycle);
    s.status = status::kRunning | status;
    producer->PublishSensors();
  };
  SensorBlock in{};
  publish(5, 0);
  ASSERT_EQ(adaptor.read(&in), ReadResult::kOk);
  std::thread paused([&] {
    for (int i = 0; i < 6; ++i) {  // 0.6 s of heartbeats, one every 0.1 s
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      publish(5, status::kPaused);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    publish(6, 0);
  });
  const double t0 = MonotonicSeconds();
  const ReadResult r = adaptor.read(&in);
  const double waited = MonotonicSeconds() - t0;
  paused.join();
  ASSERT_EQ(r, ReadResult::kOk);
  EXPECT_EQ(in.cycle, 6u);
  EXPECT_GE(waited, 0.6);
  publish(6, status::kPaused);  // a heartbeat, then none: the timeout counts from it
  const double t1 = MonotonicSeconds();
  EXPECT_EQ(adaptor.read(&in), ReadResult::kTimeout);
  EXPECT_GE(MonotonicSeconds() - t1, 0.195);
}

}  // namespace
}  // namespace ohrp::shm
