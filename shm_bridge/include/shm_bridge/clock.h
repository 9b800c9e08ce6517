// The clocks every program of the platform times with, defined once: the monotonic clock
// (CLOCK_MONOTONIC: the clock of the segment's deadlines and wake-up time stamps, of sim_host's
// real-time pacing and of hw_driver's cycle) and the calling thread's CPU time (what a benchmark
// charges to the code it runs, whatever else shares the machine). Both are vDSO calls: no system
// call, no allocation, usable on the real-time path. And the absolute sleep on the monotonic
// clock that the real-time loops pace themselves with (a system call; no allocation).
#pragma once

#include <time.h>

#include <atomic>
#include <cerrno>
#include <cstdint>

namespace ohrp {

namespace clock_internal {
inline timespec Read(clockid_t id) noexcept {
  timespec ts{};
  clock_gettime(id, &ts);
  return ts;
}
inline int64_t Ns(const timespec& ts) noexcept {
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}
inline double Seconds(const timespec& ts) noexcept {
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
// sleeps until `t` on CLOCK_MONOTONIC; a signal's interruption sleeps on, unless `stop` is set
inline void SleepUntil(const timespec& t, const std::atomic<int>* stop) noexcept {
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) == EINTR) {
    if (stop != nullptr && stop->load()) return;
  }
}
}  // namespace clock_internal

// CLOCK_MONOTONIC now [ns], [s]
inline int64_t MonotonicNs() noexcept {
  return clock_internal::Ns(clock_internal::Read(CLOCK_MONOTONIC));
}
inline double MonotonicSeconds() noexcept {
  return clock_internal::Seconds(clock_internal::Read(CLOCK_MONOTONIC));
}

// Sleeps until the absolute CLOCK_MONOTONIC time `t` [s] (or [ns]); returns at once when `t`
// has passed. A signal that interrupts the sleep does not end it, unless `stop` (may be null:
// never) is non-zero by then: a loop whose signal handler sets `stop` wakes up to end its run.
inline void SleepUntil(double t, const std::atomic<int>* stop = nullptr) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t);
  ts.tv_nsec = static_cast<long>((t - static_cast<double>(ts.tv_sec)) * 1e9);
  clock_internal::SleepUntil(ts, stop);
}
inline void SleepUntilNs(int64_t t, const std::atomic<int>* stop = nullptr) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t / 1000000000);
  ts.tv_nsec = static_cast<long>(t % 1000000000);
  clock_internal::SleepUntil(ts, stop);
}

// the calling thread's CPU time [ns], [s]
inline int64_t ThreadCpuNs() noexcept {
  return clock_internal::Ns(clock_internal::Read(CLOCK_THREAD_CPUTIME_ID));
}
inline double ThreadCpuSeconds() noexcept {
  return clock_internal::Seconds(clock_internal::Read(CLOCK_THREAD_CPUTIME_ID));
}

}  // namespace ohrp
