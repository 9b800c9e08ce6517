// The clocks every program of the platform times with, defined once: the monotonic clock
// (CLOCK_MONOTONIC: the clock of the segment's deadlines and wake-up time stamps, of sim_host's
// real-time pacing and of hw_driver's cycle) and the calling thread's CPU time (what a benchmark
// charges to the code it runs, whatever else shares the machine). Both are vDSO calls: no system
// call, no allocation, usable on the real-time path.
#pragma once

#include <time.h>

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
}  // namespace clock_internal

// CLOCK_MONOTONIC now [ns], [s]
inline int64_t MonotonicNs() noexcept {
  return clock_internal::Ns(clock_internal::Read(CLOCK_MONOTONIC));
}
inline double MonotonicSeconds() noexcept {
  return clock_internal::Seconds(clock_internal::Read(CLOCK_MONOTONIC));
}

// the calling thread's CPU time [ns], [s]
inline int64_t ThreadCpuNs() noexcept {
  return clock_internal::Ns(clock_internal::Read(CLOCK_THREAD_CPUTIME_ID));
}
inline double ThreadCpuSeconds() noexcept {
  return clock_internal::Seconds(clock_internal::Read(CLOCK_THREAD_CPUTIME_ID));
}

}  // namespace ohrp
