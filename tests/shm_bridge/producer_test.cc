// Tests the producer end across real processes: segment creation (permissions, header,
// replacement of stale objects, refusal of a live owner), removal, and WaitCommands' results
// (no controller, timeout, dead controller, stale answers, corrupted wake-up words).
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
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

class ProducerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = testing::UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    testing::RemoveSegment(name_);  // leftovers of an earlier crashed run
  }
  void TearDown() override { testing::RemoveSegment(name_); }

  std::unique_ptr<Producer> Create(Status* status = nullptr) {
    Status local;
    auto p = Producer::Create(testing::SmallConfig(name_), status ? status : &local);
    return p;
  }

  // publishes cycle `k` with q[j] = k + j / 10
  static void Publish(Producer* p, uint64_t k) {
    SensorBlock& s = p->BeginSensors();
    s.cycle = k;
    for (int j = 0; j < 3; ++j) s.q[j] = static_cast<double>(k) + 0.1 * j;
    p->PublishSensors();
  }

  bool Exists() const {
    struct stat st {};
    return stat(testing::DevShmPath(name_).c_str(), &st) == 0;
  }

  std::string name_;
};

//---------------- creation ----------------

TEST_F(ProducerTest, CreatesAnOwnerOnlySegmentEvenWithAPermissiveUmask) {
  const mode_t old_umask = umask(0);
  Status status;
  auto producer = Create(&status);
  umask(old_umask);
  ASSERT_NE(producer, nullptr) << status.message;
  EXPECT_TRUE(status.message.empty()) << status.message;
  struct stat st {};
  ASSERT_EQ(stat(testing::DevShmPath(name_).c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(static_cast<std::size_t>(st.st_size), sizeof(Segment));
  EXPECT_EQ(producer->object_name(), "ohrp_" + name_);
}

TEST_F(ProducerTest, HeaderDescribesTheConfig) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const SegmentHeader& h = producer->header();
  EXPECT_EQ(std::memcmp(h.magic, kMagic, sizeof(kMagic)), 0);
  EXPECT_EQ(h.layout_hash, LayoutHash());
  EXPECT_EQ(h.state, static_cast<uint32_t>(ProducerState::kRunning));
  EXPECT_EQ(h.producer_pid, getpid());
  EXPECT_EQ(h.controller_pid, 0);
  EXPECT_EQ(h.njoint, 3);
  EXPECT_EQ(h.nforce, 1);
  EXPECT_EQ(h.nimu, 1);
  EXPECT_STREQ(h.robot_name, "testbot");
  EXPECT_STREQ(h.joint_names[2], "ankle");
  EXPECT_EQ(h.q_min[1], -2.0);
  EXPECT_EQ(h.default_kd[2], 1.0);
  EXPECT_EQ(h.control_period, 0.005);
  EXPECT_EQ(producer->controller_pid(), 0);
}

TEST_F(ProducerTest, HeaderCarriesTheModelIdentityToAControllerProcess) {
  ProducerConfig config = testing::SmallConfig(name_);
  config.model_hash = 0x0123456789abcdefull;
  config.nbody = 4;
  config.total_mass = 12.5;
  config.joint_axis = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  config.link_mass = {3.0, 2.0, 1.5};
  Status status;
  auto producer = Producer::Create(config, &status);
  ASSERT_NE(producer, nullptr) << status.message;
  // a controller in another process sees what the producer wrote
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!adaptor.open(name_).ok()) return 1;
    const SegmentHeader& h = adaptor.header();
    if (h.model_hash != 0x0123456789abcdefull) return 2;
    if (h.nbody != 4 || h.total_mass != 12.5) return 3;
    if (h.joint_axis[0][2] != 1.0 || h.joint_axis[1][1] != 1.0 || h.joint_axis[2][0] != 1.0) {
      return 4;
    }
    if (h.joint_axis[0][0] != 0.0 || h.joint_axis[3][2] != 0.0) return 5;  // past njoint: 0
    if (h.link_mass[0] != 3.0 || h.link_mass[2] != 1.5 || h.link_mass[3] != 0.0) return 6;
    return 0;
  });
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(ProducerTest, HeaderWithoutAModelIdentityHasHashZero) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  EXPECT_EQ(producer->header().model_hash, 0u);
  EXPECT_EQ(producer->header().nbody, 0);
  EXPECT_EQ(producer->header().link_mass[0], 0.0);
}

TEST_F(ProducerTest, DestructorRemovesTheSegment) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  EXPECT_TRUE(Exists());
  producer.reset();
  EXPECT_FALSE(Exists());
}

TEST_F(ProducerTest, ReplacesTheStaleSegmentOfAKilledProducer) {
  const pid_t child = Spawn([&] {
    auto p = Create();
    if (p == nullptr) return 1;
    raise(SIGKILL);  // dies without its destructor: the object stays behind
    return 2;
  });
  ASSERT_EQ(WaitExit(child), 128 + SIGKILL);
  ASSERT_TRUE(Exists());

  Status status;
  auto producer = Create(&status);
  ASSERT_NE(producer, nullptr) << status.message;
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(status.message, "replaced stale segment '" + name_ + "' left by dead producer pid " +
                                std::to_string(child));
  EXPECT_EQ(producer->header().producer_pid, getpid());
}

TEST_F(ProducerTest, ReplacesAnObjectThatIsNotASegment) {
  {
    namespace bip = boost::interprocess;
    bip::shared_memory_object junk(bip::create_only, SegmentObjectName(name_).c_str(),
                                   bip::read_write);
    junk.truncate(100);
  }
  Status status;
  auto producer = Create(&status);
  ASSERT_NE(producer, nullptr) << status.message;
  EXPECT_NE(status.message.find("(100 bytes) that was not a robot segment"), std::string::npos)
      << status.message;
}

TEST_F(ProducerTest, RefusesASegmentOwnedByALiveProducer) {
  Pipe ready, done;
  const pid_t child = Spawn([&] {
    auto p = Create();
    if (p == nullptr) return 1;
    ready.Send();
    return done.Receive() ? 0 : 2;
  });
  ASSERT_TRUE(ready.Receive());

  Status status;
  auto producer = Create(&status);
  EXPECT_EQ(producer, nullptr);
  EXPECT_EQ(status.code, Error::kSegmentBusy);
  EXPECT_EQ(status.message, "segment '" + name_ + "' is owned by live producer pid " +
                                std::to_string(child) + "; stop it or choose another --segment");
  EXPECT_TRUE(Exists());  // the live producer's segment is untouched
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
  EXPECT_FALSE(Exists());
}

//---------------- WaitCommands ----------------

TEST_F(ProducerTest, WaitCommandsReturnsNoControllerAtOnce) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Publish(producer.get(), 0);
  CommandBlock out{};
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(producer->WaitCommands(1.0, &out), WaitResult::kNoController);
  EXPECT_LT(MonotonicSeconds() - t0, 0.01);
}

TEST_F(ProducerTest, WaitCommandsTimesOutWhileTheControllerIsSilent) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Pipe done;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    return done.Receive() ? 0 : 2;  // attached, never answers
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));
  Publish(producer.get(), 0);
  CommandBlock out{};
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(producer->WaitCommands(0.1, &out, 0.02), WaitResult::kTimeout);
  const double waited = MonotonicSeconds() - t0;
  EXPECT_GE(waited, 0.095);
  EXPECT_LT(waited, 0.5);
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
  EXPECT_EQ(producer->controller_pid(), 0);  // close released the slot
}

TEST_F(ProducerTest, WaitCommandsReportsADeadControllerWithinASlice) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    SensorBlock s{};
    CommandBlock c{};
    if (adaptor.read(&s) != ReadResult::kOk) return 2;
    adaptor.write(c);
    if (adaptor.read(&s) != ReadResult::kOk) return 3;
    usleep(50000);
    raise(SIGKILL);  // crashes holding the slot, cycle 1 unanswered
    return 4;
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));
  // the parent reaps the child as soon as it dies (until then its pid still exists)
  double reaped_at = 0.0;
  int exit_code = 0;
  std::thread reaper([&] {
    exit_code = WaitExit(child);
    reaped_at = MonotonicSeconds();
  });

  CommandBlock out{};
  Publish(producer.get(), 0);
  EXPECT_EQ(producer->WaitCommands(2.0, &out), WaitResult::kCommands);
  Publish(producer.get(), 1);
  const double t0 = MonotonicSeconds();
  const WaitResult r = producer->WaitCommands(2.0, &out, 0.02);
  const double returned_at = MonotonicSeconds();
  reaper.join();
  EXPECT_EQ(exit_code, 128 + SIGKILL);
  EXPECT_EQ(r, WaitResult::kControllerDied);
  EXPECT_LT(returned_at - t0, 1.0);
  EXPECT_LT(returned_at - reaped_at, 0.1);
  EXPECT_EQ(producer->controller_pid(), 0);
  EXPECT_EQ(producer->WaitCommands(1.0, &out), WaitResult::kNoController);
}

TEST_F(ProducerTest, WaitCommandsIgnoresAnAnswerToAnOlderCycle) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Pipe have_cycle0, answer_now;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    SensorBlock s{};
    CommandBlock c{};
    c.njoint = 3;
    if (adaptor.read(&s) != ReadResult::kOk || s.cycle != 0) return 2;
    have_cycle0.Send();
    if (!answer_now.Receive()) return 3;
    c.joint[0].q_ref = 100.0;  // late answer to cycle 0
    adaptor.write(c);
    usleep(100000);  // the producer sees the late answer alone before the right one comes
    if (adaptor.read(&s) != ReadResult::kOk || s.cycle != 1) return 4;
    c.joint[0].q_ref = 101.0;
    adaptor.write(c);
    return adaptor.read(&s) == ReadResult::kProducerStopped ? 0 : 5;
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));

  CommandBlock out{};
  Publish(producer.get(), 0);
  ASSERT_TRUE(have_cycle0.Receive());
  EXPECT_EQ(producer->WaitCommands(0.05, &out), WaitResult::kTimeout);  // child is held back
  Publish(producer.get(), 1);
  answer_now.Send();
  ASSERT_EQ(producer->WaitCommands(2.0, &out), WaitResult::kCommands);
  EXPECT_EQ(out.answers_cycle, 1u);
  EXPECT_EQ(out.joint[0].q_ref, 101.0);
  producer.reset();
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(ProducerTest, DestructorWakesABlockedReader) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    AdaptorOptions options;
    options.read_timeout = 5.0;
    options.slice = 1.0;  // the wake-up must come from the post, not from a slice check
    if (!OpenWhenReady(&adaptor, name_, options).ok()) return 1;
    SensorBlock s{};
    return adaptor.read(&s) == ReadResult::kProducerStopped ? 0 : 2;
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));
  usleep(20000);  // let the child block in read
  const double t0 = MonotonicSeconds();
  producer.reset();
  EXPECT_EQ(WaitExit(child), 0);
  EXPECT_LT(MonotonicSeconds() - t0, 0.5);
}

//---------------- corrupted wake-up words ----------------

// a scribbled commands word: WaitCommands returns at once (no wait on an untrusted word, no
// abort), every time, and sync_corrupted() says why
TEST_F(ProducerTest, WaitCommandsReportsACorruptedWakeUpWordAtOnce) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  Pipe done;
  const pid_t child = Spawn([&] {
    RobotAdaptor adaptor;
    if (!OpenWhenReady(&adaptor, name_).ok()) return 1;
    return done.Receive() ? 0 : 2;  // attached, never answers
  });
  ASSERT_TRUE(WaitFor([&] { return producer->controller_pid() == child; }));
  RawSegment raw(name_);
  raw.get()->sync.commands_ready.word = 0xdeadbeef;
  Publish(producer.get(), 0);
  CommandBlock out{};
  for (int attempt = 0; attempt < 2; ++attempt) {
    const double t0 = MonotonicSeconds();
    EXPECT_EQ(producer->WaitCommands(5.0, &out, 0.02), WaitResult::kTimeout);
    EXPECT_LT(MonotonicSeconds() - t0, 0.2);
    EXPECT_TRUE(producer->sync_corrupted());
  }
  done.Send();
  EXPECT_EQ(WaitExit(child), 0);
}

TEST_F(ProducerTest, PublishingOnACorruptedWakeUpWordIsReported) {
  auto producer = Create();
  ASSERT_NE(producer, nullptr);
  EXPECT_FALSE(producer->sync_corrupted());
  RawSegment raw(name_);
  raw.get()->sync.sensors_ready.word = 0x00010000;
  Publish(producer.get(), 0);
  EXPECT_TRUE(producer->sync_corrupted());
  CommandBlock out{};
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(producer->WaitCommands(5.0, &out), WaitResult::kTimeout);
  EXPECT_LT(MonotonicSeconds() - t0, 0.2);
}

}  // namespace
}  // namespace ohrp::shm
