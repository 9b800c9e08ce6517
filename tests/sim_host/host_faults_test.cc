// Tests sim_host as a process against faults, with the real binary: a dead, lost or stopped
// controller, a dead sim_host and its stale segment, a segment whose wake-up words are scribbled
// on, an interrupt (the fixture: host_process.h).
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/wait.h>

#include <algorithm>
#include <random>

#include "host_process.h"

namespace ohrp::sim {
namespace {

namespace fs = std::filesystem;
using testing::Clock;
using testing::SimHostProcess;
using testing::Since;

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
    shm::SensorBlock s{};
    AnswerTenCycles(&a, &s);
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

}  // namespace
}  // namespace ohrp::sim
