// What another process can do to a segment (bridge.h; src/segment_guard.h), with both ends in
// forked children of the test: a truncated file ends both ends with a result, never SIGBUS; the
// creator removes its segment on every way out (exit(), abort, a fatal or a stop signal, a
// scribbled header); a corrupted commands_ready word is a corruption on both ends in every
// trial (never a normal end); a segment of another user is refused unless allowed; a segment
// still being created is waited for.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <thread>

#include "shm_bridge/observer.h"
#include "test_util.h"

namespace ohrp::shm {
namespace {

using testing::DevShmPath;
using testing::OpenWhenReady;
using testing::Pipe;
using testing::RawSegment;
using testing::RemoveSegment;
using testing::SmallConfig;
using testing::Spawn;
using testing::UniqueSegment;
using testing::WaitExit;
using testing::WaitFor;

bool Exists(const std::string& name) { return access(DevShmPath(name).c_str(), F_OK) == 0; }

// exit codes of the children below
constexpr int kProducerFault = 20;    // + SegmentFault: the producer found its segment faulty
constexpr int kControllerResult = 10;  // + ReadResult: the controller's read or write ended
constexpr int kControllerFault = 40;   // + SegmentFault, with kSegmentCorrupted / kSyncCorrupted
constexpr int kProducerLostController = 5;  // the controller went (sim_host's exit code)

// A producer that cycles as sim_host does (publish, wait for the commands, `physics_us` of
// physics steps) until its segment is found faulty or its controller goes; then it ends its
// run (kStopped) and is destroyed.
int ProducerLoop(const std::string& name, int physics_us, Pipe* ready) {
  Status status;
  auto producer = Producer::Create(SmallConfig(name), &status);
  if (producer == nullptr) return 2;
  ready->Send();
  const double t_end = MonotonicSeconds() + 10.0;
  bool had_controller = false;
  for (uint64_t cycle = 0; MonotonicSeconds() < t_end; ++cycle) {
    if (producer->sync_corrupted()) break;
    SensorBlock& s = producer->BeginSensors();
    s.cycle = cycle;
    s.time = 0.005 * static_cast<double>(cycle);
    producer->PublishSensors();
    CommandBlock cmd{};
    const WaitResult r = producer->WaitCommands(1.0, &cmd);
    if (producer->sync_corrupted()) break;
    if (r == WaitResult::kCommands) {
      had_controller = true;
      if (physics_us > 0) usleep(physics_us);
    }
    if (r == WaitResult::kNoController || r == WaitResult::kControllerDied) {
      if (had_controller) return kProducerLostController;
      usleep(1000);
    }
  }
  const int code = producer->sync_corrupted() ? kProducerFault + static_cast<int>(producer->fault())
                                              : 1;
  producer->SetState(ProducerState::kStopped);
  return code;
}

// A controller that answers every cycle, taking `update_us` per update; sends on `cycling`
// after 20 cycles. Its exit code says how its run ended.
int ControllerLoop(const std::string& name, int update_us, Pipe* cycling) {
  RobotAdaptor a;
  if (!OpenWhenReady(&a, name).ok()) return 3;
  SensorBlock s{};
  for (int cycle = 0;; ++cycle) {
    ReadResult r = a.read(&s);
    if (r == ReadResult::kOk) {
      if (update_us > 0) usleep(update_us);
      CommandBlock c{};
      c.njoint = 3;
      r = a.write(c);
    }
    if (r == ReadResult::kSegmentCorrupted || r == ReadResult::kSyncCorrupted) {
      return kControllerFault + static_cast<int>(a.fault());
    }
    if (r != ReadResult::kOk) return kControllerResult + static_cast<int>(r);
    if (cycle == 20) cycling->Send();
  }
}

class SegmentGuardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    RemoveSegment(name_);
  }
  void TearDown() override {
    ohrp::testing::Kill(&producer_);
    ohrp::testing::Kill(&controller_);
    RemoveSegment(name_);
  }
  // starts the pair; true once the controller cycles
  bool StartPair(int update_us = 0, int physics_us = 0) {
    producer_ = Spawn([&] { return ProducerLoop(name_, physics_us, &ready_); });
    if (!ready_.Receive(5.0)) return false;
    controller_ = Spawn([&] { return ControllerLoop(name_, update_us, &cycling_); });
    return cycling_.Receive(5.0);
  }
  std::string name_;
  pid_t producer_ = -1, controller_ = -1;
  Pipe ready_, cycling_;
};

//---------------- truncation ----------------

// The file truncated under a running pair (to nothing, to its first page, to half): both ends
// end with "truncated" within a few cycles, neither by SIGBUS (128 + 7 = 135, as before).
TEST_F(SegmentGuardTest, TruncationEndsBothEndsWithAResultNotSIGBUS) {
  for (const off_t size : {off_t{0}, off_t{4096}, static_cast<off_t>(sizeof(Segment) / 2)}) {
    SCOPED_TRACE("truncated to " + std::to_string(size) + " bytes");
    ASSERT_TRUE(StartPair());
    const double t0 = MonotonicSeconds();
    ASSERT_EQ(truncate(DevShmPath(name_).c_str(), size), 0);
    EXPECT_EQ(WaitExit(&producer_, 5.0),
              kProducerFault + static_cast<int>(SegmentFault::kTruncated))
        << "20 + SegmentFault; 135: SIGBUS";
    EXPECT_EQ(WaitExit(&controller_, 5.0),
              kControllerFault + static_cast<int>(SegmentFault::kTruncated))
        << "40 + SegmentFault; 10 + ReadResult; 135: SIGBUS";
    const double ended = MonotonicSeconds() - t0;
    EXPECT_LT(ended, 1.0);
    std::printf("truncated to %ld bytes: both ends ended within %.1f ms\n",
                static_cast<long>(size), 1e3 * ended);
    EXPECT_FALSE(Exists(name_)) << "the producer removes its truncated segment";
    RemoveSegment(name_);
  }
}

// Truncated and grown again at once: the pages read as zeros (maybe without any fault); the
// size check alone would miss it, the header check does not.
TEST_F(SegmentGuardTest, ATruncatedAndRegrownFileIsAFaultToo) {
  ASSERT_TRUE(StartPair());
  const int fd = open(DevShmPath(name_).c_str(), O_RDWR);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(ftruncate(fd, 0), 0);
  ASSERT_EQ(ftruncate(fd, sizeof(Segment)), 0);
  close(fd);
  const int producer = WaitExit(&producer_, 5.0);
  const int controller = WaitExit(&controller_, 5.0);
  EXPECT_TRUE(producer == kProducerFault + static_cast<int>(SegmentFault::kHeader) ||
              producer == kProducerFault + static_cast<int>(SegmentFault::kTruncated))
      << producer;
  EXPECT_TRUE(controller == kControllerFault + static_cast<int>(SegmentFault::kHeader) ||
              controller == kControllerFault + static_cast<int>(SegmentFault::kTruncated))
      << controller;
}

// An observer watching a segment whose file is truncated gets a result, not SIGBUS.
TEST_F(SegmentGuardTest, TruncationEndsAnObserverWithAResult) {
  ASSERT_TRUE(StartPair());
  const pid_t observer = Spawn([&] {
    Observer o;
    if (!o.open(name_).ok()) return 3;
    SensorBlock s{};
    for (;;) {
      const ReadResult r = o.read(&s, 2.0);
      if (r != ReadResult::kOk) return kControllerResult + static_cast<int>(r);
    }
  });
  usleep(100000);
  ASSERT_EQ(truncate(DevShmPath(name_).c_str(), 0), 0);
  EXPECT_EQ(WaitExit(observer, 5.0),
            kControllerResult + static_cast<int>(ReadResult::kSegmentCorrupted));
}

//---------------- the creator removes its segment ----------------

// Each way out of a process that created a segment, in a forked child: the file is gone
// afterwards (before: left behind by all but the destructor).
TEST_F(SegmentGuardTest, TheCreatorRemovesItsSegmentOnEveryWayOut) {
  struct WayOut {
    const char* what;
    void (*leave)();
    int code;  // the child's exit code (128 + signal); -1: any but 0
  };
  const WayOut ways[] = {
      {"exit() on an error path, no unwinding", [] { std::exit(2); }, 2},
      {"an uncaught exception (std::terminate)",
       [] { std::thread([] { throw std::runtime_error("boom"); }).join(); }, 128 + SIGABRT},
      {"abort()", [] { std::abort(); }, 128 + SIGABRT},
      {"SIGTERM without a handler", [] { raise(SIGTERM); }, 128 + SIGTERM},
      {"SIGHUP", [] { raise(SIGHUP); }, 128 + SIGHUP},
      {"SIGSEGV", [] { raise(SIGSEGV); }, -1},  // (under AddressSanitizer: its report, exit 1)
  };
  for (const WayOut& way : ways) {
    SCOPED_TRACE(way.what);
    Pipe created;
    const pid_t child = Spawn([&] {
      Status status;
      Producer* leaked = Producer::Create(SmallConfig(name_), &status).release();
      if (leaked == nullptr) return 1;
      created.Send();
      way.leave();  // never unwinds into a destructor
      return 3;
    });
    ASSERT_TRUE(created.Receive(5.0));
    const int code = WaitExit(child, 5.0);
    if (way.code >= 0) {
      EXPECT_EQ(code, way.code);
    }
    EXPECT_GT(code, 0);
    EXPECT_FALSE(Exists(name_)) << "left behind: " << DevShmPath(name_);
    RemoveSegment(name_);
  }
}

// Another process overwrote the header (magic and producer pid among it): the destructor still
// removes the segment (before: it trusted the header's pid and left the file).
TEST_F(SegmentGuardTest, AScribbledHeaderDoesNotKeepTheCreatorFromRemovingIt) {
  Status status;
  auto producer = Producer::Create(SmallConfig(name_), &status);
  ASSERT_NE(producer, nullptr) << status.message;
  {
    RawSegment raw(name_);
    std::mt19937 random(28);
    auto* bytes = reinterpret_cast<unsigned char*>(&raw.get()->header);
    for (std::size_t i = 0; i < 256; ++i) bytes[i] = static_cast<unsigned char>(random());
  }
  EXPECT_TRUE(producer->sync_corrupted());
  EXPECT_EQ(producer->fault(), SegmentFault::kHeader);
  producer.reset();
  EXPECT_FALSE(Exists(name_));
}

// Only the creator removes: a forked child of the producer's process that exits leaves the
// segment to its parent.
TEST_F(SegmentGuardTest, AForkedChildOfTheCreatorLeavesTheSegment) {
  Status status;
  auto producer = Producer::Create(SmallConfig(name_), &status);
  ASSERT_NE(producer, nullptr) << status.message;
  const pid_t child = Spawn([] {
    std::exit(0);  // atexit handlers run in the child
    return 0;
  });
  EXPECT_EQ(WaitExit(child, 5.0), 0);
  EXPECT_TRUE(Exists(name_));
  producer.reset();
  EXPECT_FALSE(Exists(name_));
}

// A segment created again under the name by another producer (after this one's file was
// removed) is not this producer's to remove.
TEST_F(SegmentGuardTest, TheCreatorRemovesOnlyTheFileItCreated) {
  Status status;
  auto first = Producer::Create(SmallConfig(name_), &status);
  ASSERT_NE(first, nullptr) << status.message;
  RemoveSegment(name_);
  const int fd = open(DevShmPath(name_).c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  ASSERT_GE(fd, 0);
  close(fd);
  first.reset();
  EXPECT_TRUE(Exists(name_));
}

//---------------- corrupted handshake ----------------

// commands_ready overwritten at a random moment of a running pair whose producer takes 2 ms of
// physics per cycle and controller up to 1 ms per update: when the word is overwritten during
// the physics, the producer finds it first and ends its run while the controller updates. In
// every trial both ends report the corruption, neither a normal end (before: the controller
// saw "producer stopped", a normal end, in 11 of these 15 trials; posture exited 0 in 9 of 15).
TEST_F(SegmentGuardTest, ACorruptedCommandsReadyWordIsAnErrorOnBothEndsInEveryTrial) {
  std::mt19937 random(15);
  constexpr int kTrials = 15;
  int producer_first = 0;
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    ASSERT_TRUE(StartPair(static_cast<int>(random() % 1000), 2000));
    usleep(static_cast<useconds_t>(random() % 5000));
    {
      RawSegment raw(name_);
      std::atomic_ref<uint32_t>(raw.get()->sync.commands_ready.word).store(0xdeadbeefu);
    }
    const int controller = WaitExit(&controller_, 5.0);
    const int producer = WaitExit(&producer_, 5.0);
    const int words = static_cast<int>(SegmentFault::kWakeUpWords);
    EXPECT_EQ(controller, kControllerFault + words)
        << "40 + SegmentFault; 10 + ReadResult (13: producer stopped)";
    // the producer finds the word itself, or its controller leaves first over it
    EXPECT_TRUE(producer == kProducerFault + words || producer == kProducerLostController)
        << producer;
    if (producer == kProducerFault + words) ++producer_first;
    RemoveSegment(name_);
  }
  std::printf("the producer found the word in %d of %d trials\n", producer_first, kTrials);
}

// A producer whose controller found the word corrupted and left still learns why before it
// waits again (sync_corrupted() looks at the words every call).
TEST_F(SegmentGuardTest, TheProducerSeesACorruptedWordItDoesNotWaitOn) {
  Status status;
  auto producer = Producer::Create(SmallConfig(name_), &status);
  ASSERT_NE(producer, nullptr) << status.message;
  EXPECT_FALSE(producer->sync_corrupted());
  {
    RawSegment raw(name_);
    std::atomic_ref<uint32_t>(raw.get()->sync.commands_ready.word).store(4);
  }
  EXPECT_TRUE(producer->sync_corrupted());
  EXPECT_EQ(producer->fault(), SegmentFault::kWakeUpWords);
  producer->SetState(ProducerState::kStopped);
  EXPECT_EQ(producer->header().state, static_cast<uint32_t>(ProducerState::kFailed))
      << "a faulty segment is no normal end";
}

//---------------- another user's segment ----------------

// A segment whose file belongs to another user (here: 'nobody', as a squatter who created the
// name first) is refused by a controller and an observer unless allowed (before: root attached).
TEST_F(SegmentGuardTest, ASegmentOfAnotherUserIsRefusedUnlessAllowed) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to give the segment's file to another user";
  constexpr uid_t kNobody = 65534;
  Status status;
  auto producer = Producer::Create(SmallConfig(name_), &status);
  ASSERT_NE(producer, nullptr) << status.message;
  ASSERT_EQ(chown(DevShmPath(name_).c_str(), kNobody, kNobody), 0);
  unsetenv(kAllowForeignSegmentEnv);

  RobotAdaptor a;
  Status s = a.open(name_);
  EXPECT_EQ(s.code, Error::kForeignOwner) << s.message;
  EXPECT_NE(s.message.find("uid 65534"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("OHRP_ALLOW_FOREIGN_SEGMENT=1"), std::string::npos) << s.message;
  EXPECT_FALSE(a.is_open());
  EXPECT_EQ(producer->controller_pid(), 0);
  Observer o;
  EXPECT_EQ(o.open(name_).code, Error::kForeignOwner);

  AdaptorOptions allow;
  allow.allow_other_owner = true;
  s = a.open(name_, allow);
  EXPECT_TRUE(s.ok()) << s.message;
  a.close();
  setenv(kAllowForeignSegmentEnv, "1", 1);
  s = a.open(name_);
  EXPECT_TRUE(s.ok()) << s.message;
  a.close();
  unsetenv(kAllowForeignSegmentEnv);
}

//---------------- attaching during creation ----------------

// The producer has created the object but not sized it yet (0 bytes), then sizes it and writes
// its header 200 ms later: open waits and attaches (before: "not a segment" at once, exit 4).
TEST_F(SegmentGuardTest, OpenWaitsForASegmentStillBeingCreated) {
  const std::string model = UniqueSegment("model");
  Status status;
  auto producer = Producer::Create(SmallConfig(model), &status);  // the header to write
  ASSERT_NE(producer, nullptr) << status.message;
  const int fd = open(DevShmPath(name_).c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  ASSERT_GE(fd, 0);
  std::thread create([&] {
    usleep(200000);
    if (ftruncate(fd, sizeof(Segment)) != 0) return;
    void* map = mmap(nullptr, sizeof(SegmentHeader), PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (map == MAP_FAILED) return;
    std::memcpy(map, &producer->header(), sizeof(SegmentHeader));
    munmap(map, sizeof(SegmentHeader));
  });
  RobotAdaptor a;
  const double t0 = MonotonicSeconds();
  const Status s = a.open(name_);
  const double waited = MonotonicSeconds() - t0;
  create.join();
  close(fd);
  EXPECT_TRUE(s.ok()) << ErrorName(s.code) << ": " << s.message;
  EXPECT_GE(waited, 0.15);
  EXPECT_LT(waited, 0.9);
  a.close();
}

// An object that stays empty: "not ready" (the runner retries it up to --attach-timeout),
// after the wait, naming the 0 bytes.
TEST_F(SegmentGuardTest, AnObjectThatStaysEmptyIsNotReadyYet) {
  const int fd = open(DevShmPath(name_).c_str(), O_CREAT | O_EXCL | O_RDWR, 0600);
  ASSERT_GE(fd, 0);
  close(fd);
  RobotAdaptor a;
  const double t0 = MonotonicSeconds();
  const Status s = a.open(name_);
  EXPECT_EQ(s.code, Error::kProducerNotReady) << s.message;
  EXPECT_NE(s.message.find("0 bytes"), std::string::npos) << s.message;
  EXPECT_GE(MonotonicSeconds() - t0, 0.9);
}

}  // namespace
}  // namespace ohrp::shm
