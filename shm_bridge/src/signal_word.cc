// Wake-up words: post, adaptive spin, futex sleep (signal_word.h).
#include "signal_word.h"

#include <linux/futex.h>
#include <sched.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>

#include "sync.h"

namespace ohrp::shm::internal {
namespace {

constexpr int kClockCheckEvery = 32;  // spin iterations between two reads of the clock

// one pause of a spin loop: lets the sibling hardware thread run, saves power
inline void CpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield" ::: "memory");
#endif
}

// futex(2) on a word shared between processes (no FUTEX_PRIVATE_FLAG): wakes up to `n`
long FutexWake(uint32_t* word, int n) {
  return syscall(SYS_futex, word, FUTEX_WAKE, n, nullptr, nullptr, 0);
}

// sleeps while `*word` == `value`, until the absolute CLOCK_MONOTONIC time `until` at the latest
long FutexWaitUntil(uint32_t* word, uint32_t value, const timespec* until) {
  return syscall(SYS_futex, word, FUTEX_WAIT_BITSET, value, until, nullptr,
                 FUTEX_BITSET_MATCH_ANY);
}

// takes a pending post: true when the word held kSignalPosted and is now clear
inline bool TryTake(std::atomic_ref<uint32_t>& word, uint32_t seen) {
  return (seen & kSignalPosted) != 0 &&
         word.compare_exchange_strong(seen, 0, std::memory_order_acquire,
                                      std::memory_order_relaxed);
}

}  // namespace

int64_t AnswerNs(int64_t start_ns, int64_t post_ns, int64_t now_ns) {
  if (now_ns <= start_ns || post_ns <= start_ns) return 0;  // compared first: no overflow
  return std::min(post_ns, now_ns) - start_ns;
}

int64_t NextTypical(int64_t typical_ns, int64_t answer_ns) {
  answer_ns = std::clamp<int64_t>(answer_ns, 1, 2 * kMaxSpinNs);
  return typical_ns <= 0 ? answer_ns : typical_ns + (answer_ns - typical_ns) / 8;
}

int64_t SpinBudget(int64_t typical_ns) {
  if (typical_ns > kMaxSpinNs) return 0;
  return std::clamp<int64_t>(2 * typical_ns, kMinSpinNs, kMaxSpinNs);
}

bool Post(SignalWord* s) {
  std::atomic_ref<int32_t>(s->poster_cpu).store(sched_getcpu(), std::memory_order_relaxed);
  std::atomic_ref<int64_t>(s->post_ns).store(MonotonicNs(), std::memory_order_relaxed);
  std::atomic_ref<uint32_t> word(s->word);
  const uint32_t old = word.fetch_or(kSignalPosted, std::memory_order_acq_rel);
  if (!ValidSignalWord(old)) {
    FutexWake(&s->word, INT_MAX);  // a sleeper looks at the word again and sees it
    return false;
  }
  if ((old & kSignalSleeping) != 0) FutexWake(&s->word, 1);
  return true;
}

void WakeAll(SignalWord* s) { FutexWake(&s->word, INT_MAX); }

SignalResult Wait(SignalWord* s, int64_t until_ns, int64_t* typical_ns) {
  std::atomic_ref<uint32_t> word(s->word);
  const int64_t start = MonotonicNs();
  // what the peer took to answer: until its post, not until this process ran again
  const auto taken = [&] {
    const int64_t posted = std::atomic_ref<int64_t>(s->post_ns).load(std::memory_order_relaxed);
    *typical_ns = NextTypical(*typical_ns, AnswerNs(start, posted, MonotonicNs()));
    return SignalResult::kSignalled;
  };

  // pass a bounded time without sleeping: spin while the poster runs on another CPU, hand
  // the CPU over (sched_yield) while it shares ours, so that it can run and post
  const int own_cpu = sched_getcpu();
  const int poster_cpu = std::atomic_ref<int32_t>(s->poster_cpu).load(std::memory_order_relaxed);
  const bool same_cpu = own_cpu >= 0 && own_cpu == poster_cpu;
  const int64_t budget = SpinBudget(*typical_ns);
  const int64_t spin_until = std::min(until_ns, start + budget);
  for (int i = 1;; ++i) {
    const uint32_t v = word.load(std::memory_order_relaxed);
    if (!ValidSignalWord(v)) return SignalResult::kCorrupt;
    if (TryTake(word, v)) return taken();
    if (budget == 0) break;
    if (same_cpu) {
      if (MonotonicNs() >= spin_until) break;
      sched_yield();
    } else {
      if (i % kClockCheckEvery == 0 && MonotonicNs() >= spin_until) break;
      CpuRelax();
    }
  }

  // then sleep, announcing it with kSignalSleeping so that the poster wakes us; the futex
  // timeout is the absolute CLOCK_MONOTONIC time until_ns (FUTEX_WAIT_BITSET)
  const timespec until = ToTimespec(std::max<int64_t>(until_ns, 0));
  for (;;) {
    uint32_t v = word.load(std::memory_order_relaxed);
    if (!ValidSignalWord(v)) return SignalResult::kCorrupt;
    if (TryTake(word, v)) return taken();
    if ((v & kSignalSleeping) == 0) {
      if (!word.compare_exchange_strong(v, v | kSignalSleeping, std::memory_order_relaxed)) {
        continue;  // a post (or a scribble) came in between: look again
      }
      v |= kSignalSleeping;
    }
    if (FutexWaitUntil(&s->word, v, &until) == 0) continue;
    if (errno == ETIMEDOUT) {
      word.fetch_and(~kSignalSleeping, std::memory_order_relaxed);
      *typical_ns = NextTypical(*typical_ns, MonotonicNs() - start);  // a slow peer stops the spin
      return SignalResult::kTimeout;
    }
    if (errno != EAGAIN && errno != EINTR) {
      return SignalResult::kCorrupt;  // EFAULT, EINVAL, ENOSYS: the word is not usable
    }
  }
}

}  // namespace ohrp::shm::internal
