// The clocks every program of the platform times with, defined once: the monotonic clock
// (CLOCK_MONOTONIC: the clock of the segment's deadlines and wake-up time stamps, of sim_host's
// real-time pacing and of hw_driver's cycle) and the calling thread's CPU time (what a benchmark
// charges to the code it runs, whatever else shares the machine). Both are vDSO calls: no system
// call, no allocation, usable on the real-time path.
#pragma once

#include <time.h>

#include <cstdint>

namespace ohrp {

// CLOCK_MONOTONIC now [ns]
inline int64_t MonotonicNs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

// CLOCK_MONOTONIC now [s]
inline double MonotonicSeconds() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// the calling thread's CPU time [ns]
inline int64_t ThreadCpuNs() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

// the calling thread's CPU time [s]
inline double ThreadCpuSeconds() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

}  // namespace ohrp
