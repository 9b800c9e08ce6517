// The handshake's wake-up words (protocol: layout.h): a post that sets a bit and makes the wake
// system call only for a sleeping waiter, and a wait that stays awake for a bounded, adaptive
// time (spinning, or yielding when both ends share a CPU) before it sleeps in FUTEX_WAIT.
// Real-time safe: no allocation, no exceptions, no logging. A word holding a value the bridge
// never writes is reported as kCorrupt, never trusted.
#pragma once

#include <cstdint>

#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

inline constexpr int64_t kMaxSpinNs = 100000;  // a waiter never spins longer than this
inline constexpr int64_t kMinSpinNs = 2000;    // nor, when it spins at all, shorter than this

enum class SignalResult {
  kSignalled,  // a post was taken (the word is clear again)
  kTimeout,    // `until_ns` passed; a post arriving later stays pending for the next wait
  kCorrupt,    // the word holds bits the bridge never sets (or the futex call failed)
};

// True when `value` is a value the bridge writes into a wake-up word.
constexpr bool ValidSignalWord(uint32_t value) {
  return (value & ~(kSignalPosted | kSignalSleeping)) == 0;
}

// How long [ns] the next wait passes without sleeping: 0 when recent waits took longer than
// kMaxSpinNs (sleeping costs less than waiting awake would), else about twice the typical
// wait, within [kMinSpinNs, kMaxSpinNs]. `typical_ns`: see Wait.
int64_t SpinBudget(int64_t typical_ns);

// Posts `s`: sets kSignalPosted (at most one post pends) and wakes a sleeping waiter. Records
// the caller's CPU for the waiter's spin. False when the word held a corrupted value (every
// sleeper is then woken, to see it).
bool Post(SignalWord* s);

// Takes the post of `s`, waiting until the CLOCK_MONOTONIC time `until_ns` at the latest.
// For SpinBudget it stays awake: it spins when the poster last ran on another CPU, and hands
// its CPU over (sched_yield) when the poster last ran on the same CPU, so that two processes on
// one CPU never spin against each other; then it sleeps in FUTEX_WAIT until the post. `*typical_ns` is the waiter's own moving average of what
// its waits took [ns] (0: none measured yet); the wait updates it.
// Only one process may wait on a word at a time (a second waiter is not lost, but may sleep
// until `until_ns`).
SignalResult Wait(SignalWord* s, int64_t until_ns, int64_t* typical_ns);

// Wakes every sleeper of `s` without posting (a producer ending its run).
void WakeAll(SignalWord* s);

}  // namespace ohrp::shm::internal
