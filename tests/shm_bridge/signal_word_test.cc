// Tests the handshake's wake-up words (shm_bridge/src/signal_word.h) on words in shared memory:
// post and wait, at most one pending post, timeouts, corrupted words, the spin budget, a wake-up
// from sleep across processes, and two processes on one CPU that hand the CPU over instead of
// spinning against each other.
#include <sched.h>
#include <sys/mman.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "signal_word.h"
#include "sync.h"
#include "test_util.h"

namespace ohrp::shm::internal {
namespace {

using testing::Spawn;
using testing::WaitExit;

// two wake-up words in memory shared with forked children, as in a segment
class SignalWordTest : public ::testing::Test {
 protected:
  void SetUp() override {
    void* mem = mmap(nullptr, sizeof(Sync), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS,
                     -1, 0);
    ASSERT_NE(mem, MAP_FAILED);
    sync_ = static_cast<Sync*>(mem);
    sync_->sensors_ready = {0, -1, 0};
    sync_->commands_ready = {0, -1, 0};
  }
  void TearDown() override { munmap(sync_, sizeof(Sync)); }

  Sync* sync_ = nullptr;
};

// pins the calling process to `cpu`; false when it may not run there
bool PinTo(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return sched_setaffinity(0, sizeof(set), &set) == 0;
}

// the CPUs this process may use
std::vector<int> AllowedCpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  }
  return cpus;
}

//---------------- the spin budget ----------------

TEST(SpinBudget, FollowsTheTypicalAnswerWithinItsBounds) {
  EXPECT_EQ(SpinBudget(0), kMinSpinNs);           // nothing learnt yet: the shortest spin
  EXPECT_EQ(SpinBudget(500), kMinSpinNs);
  EXPECT_EQ(SpinBudget(30000), 60000);            // twice the typical answer
  EXPECT_EQ(SpinBudget(kMaxSpinNs), kMaxSpinNs);  // never more than the maximum
  EXPECT_EQ(SpinBudget(kMaxSpinNs + 1), 0);       // slow peers: sleep at once
}

// The spin follows how long the peer took to post, not how long this process took to run
// again. (Learning the whole wait made two processes on two CPUs sleep for ever once a few slow
// wake-ups had turned the spin off: each wait then included a wake-up.)
TEST(AnswerNs, IsTheTimeOfThePostNotOfTheWakeUp) {
  EXPECT_EQ(AnswerNs(1000, 4000, 900000), 3000);  // posted after 3 us, ran again after 899 us
  EXPECT_EQ(AnswerNs(1000, 500, 2000), 0);        // posted before the wait began
  EXPECT_EQ(AnswerNs(1000, INT64_MAX, 2000), 1000);  // a scribbled stamp: the wait at most
  EXPECT_EQ(AnswerNs(1000, INT64_MIN, 2000), 0);
}

TEST(NextTypical, AveragesAndBoundsEachAnswer) {
  EXPECT_EQ(NextTypical(0, 3000), 3000);  // the first answer sets it
  EXPECT_EQ(NextTypical(3000, 11000), 4000);
  EXPECT_EQ(NextTypical(30000, 1000000000), 30000 + (2 * kMaxSpinNs - 30000) / 8);
  // answers that stay slow turn the spin off, fast ones turn it on again
  int64_t typical = 30000;
  for (int i = 0; i < 30; ++i) typical = NextTypical(typical, 4 * kMaxSpinNs);
  EXPECT_EQ(SpinBudget(typical), 0);
  for (int i = 0; i < 30; ++i) typical = NextTypical(typical, 5000);
  EXPECT_GT(SpinBudget(typical), 0);
}

// A single slow answer (a peer preempted for a time slice) does not turn the spin off: one
// answer counts at most 2 * kMaxSpinNs in the average.
TEST_F(SignalWordTest, OneSlowAnswerDoesNotTurnTheSpinOff) {
  int64_t typical = 30000;
  EXPECT_EQ(Wait(&sync_->commands_ready, MonotonicNs() + 20000000, &typical), SignalResult::kTimeout);
  EXPECT_LE(typical, kMaxSpinNs);
  EXPECT_GT(SpinBudget(typical), 0);
}

//---------------- post and wait in one process ----------------

TEST_F(SignalWordTest, APostIsTakenOnceAndAtMostOnePends) {
  int64_t typical = 0;
  ASSERT_TRUE(Post(&sync_->sensors_ready));
  ASSERT_TRUE(Post(&sync_->sensors_ready));  // a second post before the wait: still one
  EXPECT_EQ(sync_->sensors_ready.word, kSignalPosted);
  EXPECT_EQ(sync_->sensors_ready.poster_cpu, sched_getcpu());
  EXPECT_EQ(Wait(&sync_->sensors_ready, MonotonicNs() + 1000000000, &typical),
            SignalResult::kSignalled);
  EXPECT_EQ(sync_->sensors_ready.word, 0u);
  EXPECT_GT(typical, 0);
  EXPECT_EQ(Wait(&sync_->sensors_ready, MonotonicNs() + 20000000, &typical), SignalResult::kTimeout);
}

TEST_F(SignalWordTest, AWaitTimesOutAtItsDeadlineAndLeavesTheWordClear) {
  int64_t typical = 0;
  const int64_t t0 = MonotonicNs();
  EXPECT_EQ(Wait(&sync_->commands_ready, t0 + 30000000, &typical), SignalResult::kTimeout);
  const int64_t took = MonotonicNs() - t0;
  EXPECT_GE(took, 30000000);
  EXPECT_LT(took, 500000000);
  EXPECT_EQ(sync_->commands_ready.word, 0u);  // the sleeping bit is cleared again
  EXPECT_GT(typical, kMaxSpinNs);             // the first wait, that long, turns the spin off
  // a deadline already past: no wait at all
  EXPECT_EQ(Wait(&sync_->commands_ready, MonotonicNs() - 1000, &typical), SignalResult::kTimeout);
}

// any value the bridge never writes is reported by both ends at once, never waited on
TEST_F(SignalWordTest, CorruptedWordsAreReportedAtOnce) {
  for (const uint32_t bad : {4u, 0x80000000u, 0xdeadbeefu, 0xffffffffu}) {
    SCOPED_TRACE(bad);
    int64_t typical = 0;
    sync_->commands_ready.word = bad;
    const int64_t t0 = MonotonicNs();
    EXPECT_EQ(Wait(&sync_->commands_ready, t0 + 2000000000, &typical), SignalResult::kCorrupt);
    EXPECT_LT(MonotonicNs() - t0, 100000000);
    EXPECT_FALSE(Post(&sync_->commands_ready));
  }
  EXPECT_TRUE(ValidSignalWord(0));
  EXPECT_TRUE(ValidSignalWord(kSignalPosted | kSignalSleeping));
  EXPECT_FALSE(ValidSignalWord(4));
}

//---------------- across processes ----------------

// a waiter that sleeps (its waits were slow: no spin) is woken by a post from another process,
// and a waiter asleep when its word is scribbled on learns it from the next post
TEST_F(SignalWordTest, ASleepingWaiterInAnotherProcessIsWokenByAPost) {
  Sync* sync = sync_;
  const pid_t child = Spawn([sync] {
    int64_t typical = 10 * kMaxSpinNs;  // slow peer: sleep at once
    const int64_t t0 = MonotonicNs();
    if (Wait(&sync->sensors_ready, t0 + 5000000000, &typical) != SignalResult::kSignalled) {
      return 1;
    }
    if (MonotonicNs() - t0 > 2000000000) return 2;  // not woken: it slept to its deadline
    typical = 10 * kMaxSpinNs;
    return Wait(&sync->sensors_ready, MonotonicNs() + 5000000000, &typical) == SignalResult::kCorrupt
               ? 0
               : 3;
  });
  usleep(100000);  // the child is asleep by now
  EXPECT_EQ(sync_->sensors_ready.word, kSignalSleeping);
  EXPECT_TRUE(Post(&sync_->sensors_ready));
  usleep(100000);
  sync_->sensors_ready.word = 0x5a5a5a5a;  // a scribbler
  EXPECT_FALSE(Post(&sync_->sensors_ready));
  const double t0 = MonotonicSeconds();
  EXPECT_EQ(WaitExit(child, 5.0), 0);
  EXPECT_LT(MonotonicSeconds() - t0, 1.0);
}

// Two processes pinned to one CPU play ping-pong: a waiter must hand the CPU to its peer, not
// spin against it (a spin that cannot see the post would burn its whole budget, at least
// kMinSpinNs of CPU, every round). Judged on this thread's CPU time, not the wall clock: a third
// process sharing the CPU (a busy CI machine) lengthens the round trips but not the CPU spent.
TEST_F(SignalWordTest, TwoProcessesOnOneCpuDoNotSpinAgainstEachOther) {
  const std::vector<int> cpus = AllowedCpus();
  ASSERT_FALSE(cpus.empty());
  const int cpu = cpus.front();
  constexpr int kRounds = 2000;
  Sync* sync = sync_;
  const pid_t child = Spawn([sync, cpu] {
    if (!PinTo(cpu)) return 1;
    int64_t typical = 0;
    for (int k = 0; k < kRounds; ++k) {
      if (Wait(&sync->sensors_ready, MonotonicNs() + 5000000000, &typical) != SignalResult::kSignalled) {
        return 2;
      }
      if (!Post(&sync->commands_ready)) return 3;
    }
    return 0;
  });
  cpu_set_t original;
  sched_getaffinity(0, sizeof(original), &original);
  ASSERT_TRUE(PinTo(cpu));
  std::vector<double> us;
  int64_t typical = 0;
  for (int k = 0; k < kRounds; ++k) {
    const int64_t t0 = ThreadCpuNs();
    ASSERT_TRUE(Post(&sync_->sensors_ready));
    ASSERT_EQ(Wait(&sync_->commands_ready, MonotonicNs() + 5000000000, &typical),
              SignalResult::kSignalled);
    us.push_back(1e-3 * static_cast<double>(ThreadCpuNs() - t0));
  }
  sched_setaffinity(0, sizeof(original), &original);
  EXPECT_EQ(WaitExit(child, 5.0), 0);
  std::sort(us.begin(), us.end());
  // a hand-over costs a few system calls; a spin against the peer at least kMinSpinNs
  EXPECT_LT(us[us.size() / 2], 0.5e-3 * kMinSpinNs) << "median CPU time of a round trip [us]";
}

// On two CPUs the waiters spin instead of sleeping: a round trip takes microseconds, not the
// tens of microseconds of a wake-up from sleep (checked loosely: the machine may be busy).
TEST_F(SignalWordTest, TwoProcessesOnTwoCpusExchangeEveryPost) {
  const std::vector<int> cpus = AllowedCpus();
  if (cpus.size() < 2) GTEST_SKIP() << "one CPU only";
  constexpr int kRounds = 5000;
  Sync* sync = sync_;
  const int other = cpus[1];
  const pid_t child = Spawn([sync, other] {
    if (!PinTo(other)) return 1;
    int64_t typical = 0;
    for (int k = 0; k < kRounds; ++k) {
      if (Wait(&sync->sensors_ready, MonotonicNs() + 5000000000, &typical) != SignalResult::kSignalled) {
        return 2;
      }
      if (!Post(&sync->commands_ready)) return 3;
    }
    return 0;
  });
  cpu_set_t original;
  sched_getaffinity(0, sizeof(original), &original);
  ASSERT_TRUE(PinTo(cpus[0]));
  std::vector<double> us;
  int64_t typical = 0;
  for (int k = 0; k < kRounds; ++k) {
    const int64_t t0 = MonotonicNs();
    ASSERT_TRUE(Post(&sync_->sensors_ready));
    ASSERT_EQ(Wait(&sync_->commands_ready, MonotonicNs() + 5000000000, &typical),
              SignalResult::kSignalled);
    us.push_back(1e-3 * static_cast<double>(MonotonicNs() - t0));
  }
  sched_setaffinity(0, sizeof(original), &original);
  EXPECT_EQ(WaitExit(child, 5.0), 0);
  std::sort(us.begin(), us.end());
  EXPECT_LT(us[us.size() / 2], 20.0) << "median round trip [us]";
  EXPECT_LE(typical, kMaxSpinNs);  // the spin stays on
}

}  // namespace
}  // namespace ohrp::shm::internal
