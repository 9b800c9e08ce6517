// The handshake's wake-up words (protocol: layout.h): a post that sets a bit and makes the wake
// system call only for a sleeping waiter, and a wait that stays awake for a bounded, adaptive
// time (spinning, or yielding when both ends share a CPU) before it sleeps in FUTEX_WAIT.
// Real-time safe: no allocation, no exceptions, no logging. A word holding a value the bridge
// never writes is reported as kCorrupt, never trusted.
#pragma once

#include <cstdint>

#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

inline constexpr int64_t kMaxSpinNs = 300000;   // a waiter never spins longer than this
inline constexpr int64_t kMinSpinNs = 20000;   // nor, when it spins at all, shorter than this
                                               // (about what a wake-up from sleep costs)

enum class SignalResult {
  kSignalled,  // a post was taken (the word is clear again)
  kTimeout,    // `until_ns` passed; a post arriving later stays pending for the next wait
  kCorrupt,    // the word holds bits the bridge never sets (or the futex call failed)
};

// True when `value` is a value the bridge writes into a wake-up word.
constexpr bool ValidSignalWord(uint32_t value) {
  return (value & ~(kSignalPosted | kSignalSleeping)) == 0;
}

// How long the peer took to answer a wait that started at `start_ns` [ns]: until the post's
// time stamp `post_ns`, not until the waiter ran again at `now_ns` (its own wake-up latency
// must not turn its spin off); within [0, now_ns - start_ns] whatever the stamp says (a post
// pending before the wait answered at once; a scribbled stamp is bounded).
int64_t AnswerNs(int64_t start_ns, int64_t post_ns, int64_t now_ns);

// The moving average of the peer's answers [ns] after one more, weighted 1/8 (the first answer
// sets it). One answer counts at most 2 * kMaxSpinNs, so that a single slow one (a peer
// preempted for a time slice) does not turn the spin off; answers that stay slow do.
int64_t NextTypical(int64_t typical_ns, int64_t answer_ns);

// How long [ns] the next wait passes without sleeping: 0 when the peer's recent answers took
// longer than kMaxSpinNs (sleeping costs less than waiting awake would), else about twice the
// typical answer, within [kMinSpinNs, kMaxSpinNs]. `typical_ns`: see Wait.
int64_t SpinBudget(int64_t typical_ns);

// Posts `s`: sets kSignalPosted (at most one post pends) and wakes a sleeping waiter. Records
// the caller's CPU and the time for the waiter's spin. False when the word held a corrupted
// value (every sleeper is then woken, to see it).
bool Post(SignalWord* s);

// Takes the post of `s`, waiting until the CLOCK_MONOTONIC time `until_ns` at the latest.
// For SpinBudget it stays awake: it spins when the poster last ran on another CPU, and hands
// its CPU over (sched_yield) when the poster last ran on the same CPU, so that two processes on
// one CPU never spin against each other; then it sleeps in FUTEX_WAIT until the post.
// `*typical_ns` is the waiter's own moving average of how long its peer took to answer [ns]
// (from the start of a wait to the post's time stamp; a wait that timed out counts whole; 0:
// none measured yet); the wait updates it.
// Only one process may wait on a word at a time (a second waiter is not lost, but may sleep
// until `until_ns`).
SignalResult Wait(SignalWord* s, int64_t until_ns, int64_t* typical_ns);

// Wakes every sleeper of `s` without posting (a producer ending its run).
void WakeAll(SignalWord* s);

}  // namespace ohrp::shm::internal
