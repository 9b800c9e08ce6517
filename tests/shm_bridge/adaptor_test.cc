// Tests the robot adaptor (controller end) across real processes: every refusal of open (a
// header with corrupt counts, gains or periods among them), the
// controller slot, the lock-step ping-pong with data checks, a late controller answering the
// pending cycle, read's results when nothing comes or the producer dies, and both ends facing
// wake-up words that another process scribbles on.
#include <gtest/gtest.h>

#include <cmath>
#include <atomic>
#include <cstring>
#include <random>
#include <string>
#include <thread>

#include "shm_bridge/bridge.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::OpenWhenReady;
using testing::Pipe;
using testing::RawSegment;
using testing::Spawn;
using testing::WaitExit;
using testing::WaitFor;

class AdaptorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = testing::UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    testing::RemoveSegment(name_);  // leftovers of an earlier crashed run
  }
  void TearDown() override { testing::RemoveSegment(name_); }

  std::unique_ptr<Producer> Create() {
    Status status;
    auto p = Producer::Create(testing::SmallConfig(name_), &status);
    EXPECT_TRUE(status.ok()) << status.message;
    return p;
  }

  static bool Contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  }

  std::string name_;
};

// the data of cycle k: values that differ per cycle and per joint
double SensorValue(uint64_t k, int j) { return 1000.0 * static_cast<double>(k) + j + 0.25; }
double CommandValue(uint64_t k, int j) { return -SensorValue(k, j); }

//---------------- open: refusals ----------------

TEST_F(AdaptorTest, OpenReportsAMissingSegment) {
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNoSegment);
  EXPECT_EQ(s.message, "no segment '" + name_ + "' (/dev/shm/ohrp_" + name_ +
                           "): is sim_host or hw_driver running with --segment " + name_ + "?");
  EXPECT_FALSE(adaptor.is_open());
}

TEST_F(AdaptorTest, OpenRefusesAnObjectThatIsNotASegment) {
  namespace bip = boost::interprocess;
  {
    bip::shared_memory_object junk(bip::create_only, SegmentObjectName(name_).c_str(),
                                   bip::read_write);
    junk.truncate(100);
  }
  RobotAdaptor adaptor;
  Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNotASegment) << s.message;
  EXPECT_TRUE(Contains(s.message, "100 bytes")) << s.message;

  // full size, but filled with garbage
  {
    bip::shared_memory_object junk(bip::open_only, SegmentObjectName(name_).c_str(),
                                   bip::read_write);
    junk.truncate(sizeof(Segment));
    bip::mapped_region region(junk, bip::read_write);
    std::memset(region.get_address(), 0xab, region.get_size());
  }
  s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kNotASegment) << s.message;
  EXPECT_TRUE(Contains(s.message, "magic")) << s.message;
  EXPECT_FALSE(adaptor.is_open());
}

TEST_F(AdaptorTest, OpenRefusesAnotherLayoutHash) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  raw.get()->header.layout_hash ^= 0x5a5a;
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kLayoutMismatch);
  EXPECT_TRUE(Contains(s.message, "rebuild the controller against this producer's shm_bridge"))
      << s.message;
  char expected_hash[32];
  std::snprintf(expected_hash, sizeof(expected_hash), "0x%016llx",
                static_cast<unsigned long long>(LayoutHash()));
  EXPECT_TRUE(Contains(s.message, expected_hash)) << s.message;
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), 0);  // nothing stays attached
}

TEST_F(AdaptorTest, OpenReportsADeadProducer) {
  const pid_t child = Spawn([&] {
    auto p = Create();
    raise(SIGKILL);
    return 1;
  });
  ASSERT_EQ(WaitExit(child), 128 + SIGKILL);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerDead) << s.message;
  EXPECT_TRUE(Contains(s.message, "stale segment '" + name_ + "'")) << s.message;
  EXPECT_TRUE(Contains(s.message, "pid " + std::to_string(child))) << s.message;
  EXPECT_TRUE(Contains(s.message, "restart the producer")) << s.message;
}

TEST_F(AdaptorTest, OpenReportsAStoppedProducer) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  producer->SetState(ProducerState::kFailed);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerStopped) << s.message;
  EXPECT_TRUE(Contains(s.message, "failed")) << s.message;
}

TEST_F(AdaptorTest, OpenWaitsBrieflyForAProducerStillCreating) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  producer->SetState(ProducerState::kCreating);
  std::thread finish([&] {
    usleep(100000);
    producer->SetState(ProducerState::kRunning);
  });
  RobotAdaptor adaptor;
  const double t0 = MonotonicSeconds();
  const Status s = adaptor.open(name_);
  const double waited = MonotonicSeconds() - t0;
  finish.join();
  EXPECT_TRUE(s.ok()) << s.message;
  EXPECT_GE(waited, 0.09);
  EXPECT_LT(waited, 0.9);
}

TEST_F(AdaptorTest, OpenReportsAProducerThatStaysInCreation) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  producer->SetState(ProducerState::kCreating);
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kProducerNotReady) << s.message;
  EXPECT_FALSE(adaptor.is_open());
}

// a header of the right layout whose values are corrupt: refused with the field and the value
struct CorruptHeader {
  const char* what;                         // the field as the message names it
  void (*corrupt)(SegmentHeader* h);
  const char* expected;                     // part of the message
};

TEST_F(AdaptorTest, OpenRefusesAHeaderWithNonPhysicalValues) {
  const CorruptHeader cases[] = {
      {"njoint", [](SegmentHeader* h) { h->njoint = 100000; }, "njoint = 100000 is outside [0, 64]"},
      {"nforce", [](SegmentHeader* h) { h->nforce = -1; }, "nforce = -1 is outside [0, 4]"},
      {"nimu", [](SegmentHeader* h) { h->nimu = 3; }, "nimu = 3 is outside [0, 2]"},
      {"default_kp", [](SegmentHeader* h) { h->default_kp[1] = -200.0; },
       "default_kp[1] = -200 (joint 'knee') must be finite and >= 0"},
      {"default_kd", [](SegmentHeader* h) { h->default_kd[2] = NAN; },
       "default_kd[2] = nan (joint 'ankle') must be finite and >= 0"},
      {"q_min > q_max", [](SegmentHeader* h) { h->q_min[0] = 2.0; },
       "q_min[0] = 2 and q_max[0] = 1 (joint 'hip') are not a range"},
      {"tau_max", [](SegmentHeader* h) { h->tau_max[0] = -1.0; },
       "tau_max[0] = -1 (joint 'hip') must be >= 0"},
      {"control_period", [](SegmentHeader* h) { h->control_period = 0.0; },
       "control_period = 0 must be finite and > 0"},
      {"control_period NaN", [](SegmentHeader* h) { h->control_period = NAN; },
       "control_period = nan"},
      {"physics_period", [](SegmentHeader* h) { h->physics_period = -0.001; },
       "physics_period = -0.001 must be in [0, control_period = 0.005]"},
      {"read_timeout_hint", [](SegmentHeader* h) { h->read_timeout_hint = INFINITY; },
       "read_timeout_hint = inf"},
      {"total_mass", [](SegmentHeader* h) { h->total_mass = -3.0; }, "total_mass = -3"},
  };
  for (const CorruptHeader& c : cases) {
    SCOPED_TRACE(c.what);
    auto producer = Create();
    ASSERT_NE(producer, nullptr);
    RawSegment raw(name_);
    c.corrupt(&raw.get()->header);
    RobotAdaptor adaptor;
    const Status s = adaptor.open(name_);
    EXPECT_EQ(s.code, Error::kInvalidHeader) << s.message;
    EXPECT_TRUE(Contains(s.message, c.expected)) << s.message;
    EXPECT_TRUE(Contains(s.message, "segment '" + name_ + "'")) << s.message;
    EXPECT_FALSE(adaptor.is_open());
    EXPECT_EQ(producer->controller_pid(), 0);  // nothing stays attached
  }
}

TEST_F(AdaptorTest, OpenAcceptsUnlimitedJointsAndAHardwarePeriod) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RawSegment raw(name_);
  raw.get()->header.q_min[0] = -INFINITY;  // a joint without limits
  raw.get()->header.q_max[0] = INFINITY;
  raw.get()->header.tau_max[1] = INFINITY;
  raw.get()->header.physics_period = 0.0;  // hardware
  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_TRUE(s.ok()) << s.message;
}

//---------------- open: the controller slot ----------------

TEST_F(AdaptorTest, SecondControllerIsRefused) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Pipe attached, done;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!adaptor.open(name_).ok()) return 1;
    attached.Send();
    return done.Receive() ? 0 : 2;
  });
  ASSERT_TRUE(attached.Receive());

  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_EQ(s.code, Error::kControllerPresent);
  EXPECT_EQ(s.message, "segment '" + name_ + "' already has a controller (pid " +
                           std::to_string(child) + "); stop it first");
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), child);
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(AdaptorTest, DeadControllersSlotIsTakenOver) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!adaptor.open(name_).ok()) return 1;
    raise(SIGKILL);  // never closes
    return 2;
  });
  ASSERT_EQ(WaitExit(child), 128 + SIGKILL);
  ASSERT_EQ(producer->controller_pid(), child);

  RobotAdaptor adaptor;
  const Status s = adaptor.open(name_);
  EXPECT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(producer->controller_pid(), getpid());
  EXPECT_EQ(adaptor.header().controller_pid, getpid());
}

TEST_F(AdaptorTest, CloseReleasesTheSlotAndIsIdempotent) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  EXPECT_EQ(producer->controller_pid(), getpid());
  EXPECT_EQ(adaptor.header().njoint, 3);
  EXPECT_STREQ(adaptor.header().joint_names[1], "knee");
  adaptor.close();
  adaptor.close();
  EXPECT_FALSE(adaptor.is_open());
  EXPECT_EQ(producer->controller_pid(), 0);
  SensorBlock s{};
  EXPECT_EQ(adaptor.read(&s), ReadResult::kNotOpen);
  EXPECT_EQ(adaptor.write(CommandBlock{}), ReadResult::kNotOpen);
}

// a controller the producer let go (it missed the producer's timeout) learns it on its next
// write and read, writes nothing more, and the slot is free for a new controller
TEST_F(AdaptorTest, ADroppedControllerLearnsItOnItsNextWriteAndRead) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  RobotAdaptor adaptor;
  ASSERT_TRUE(adaptor.open(name_).ok());
  producer->BeginSensors().cycle = 1;
  producer->PublishSensors();
  SensorBlock s{};
  ASSERT_EQ(adaptor.read(&s), ReadResult::kOk);

  EXPECT_FALSE(producer->DropController(getpid() + 1));  // not the holder: nothing changes
  EXPECT_FALSE(adaptor.dropped());
  EXPECT_TRUE(producer->DropController(getpid()));
  EXPECT_EQ(producer->controller_pid(), 0);
  EXPECT_TRUE(adaptor.dropped());
  CommandBlock c{};
  c.njoint = 3;
  EXPECT_EQ(adaptor.write(c), ReadResult::kDropped);
  CommandBlock out{};
  EXPECT_EQ(producer->WaitCommands(0.05, &out), WaitResult::kNoController);  // nothing posted
  producer->BeginSensors().cycle = 2;
  producer->PublishSensors();
  EXPECT_EQ(adaptor.read(&s), ReadResult::kDropped);
  EXPECT_STREQ(ReadResultName(ReadResult::kDropped), "dropped by the producer");

  // a new controller attaches; closing the dropped adaptor leaves its claim alone
  const pid_t child = Spawn([&] {
    RobotAdaptor b;
    if (!b.open(name_).ok()) return 1;
    raise(SIGKILL);  // never closes: its claim stays
    return 2;
  });
  EXPECT_EQ(WaitExit(child), 128 + SIGKILL);
  EXPECT_EQ(producer->controller_pid(), child);
  adaptor.close();
  EXPECT_EQ(producer->controller_pid(), child);
}

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

}  // namespace
}  // namespace ohrp::shm
