// Timing one control cycle in the controller benchmarks (bench_balance, bench_walk): each call
// is timed twice, wall time (steady_clock; includes being preempted on a loaded machine) and the
// thread's CPU time (CLOCK_THREAD_CPUTIME_ID; excludes it, but its clock is a system call, whose
// cost, measured on empty pairs of reads, is subtracted when printing).
#pragma once

#include <time.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "shm_bridge/bridge.h"
#include "quantile.h"  // Quantile
#include "shm_bridge/clock.h"

namespace ohrp::bench {

// the cost of reading the thread CPU clock (the median of back-to-back reads) [s]
inline double ThreadCpuOverhead() {
  std::vector<double> d(2000);
  for (double& x : d) {
    const double t0 = ThreadCpuSeconds();
    x = ThreadCpuSeconds() - t0;
  }
  return Quantile(d, 0.5);
}

// the wall and thread CPU times of calls [s]
struct CycleTimes {
  std::vector<double> wall, cpu;

  // calls f() and records its times (the wall clock inside the CPU clock: its reads are cheap,
  // the CPU clock's are not)
  template <typename F>
  void Time(F&& f) {
    const double c0 = ThreadCpuSeconds(), w0 = MonotonicSeconds();
    f();
    const double w1 = MonotonicSeconds(), c1 = ThreadCpuSeconds();
    cpu.push_back(c1 - c0);
    wall.push_back(w1 - w0);
  }
};

// one table row [us]: wall median, p90, p99, then thread CPU median, p90, p99
inline void PrintRow(const char* name, const CycleTimes& t, double cpu_overhead) {
  std::printf("%-44s %8.2f %8.2f %8.2f   %8.2f %8.2f %8.2f\n", name, Quantile(t.wall, 0.5) * 1e6,
              Quantile(t.wall, 0.9) * 1e6, Quantile(t.wall, 0.99) * 1e6,
              (Quantile(t.cpu, 0.5) - cpu_overhead) * 1e6,
              (Quantile(t.cpu, 0.9) - cpu_overhead) * 1e6,
              (Quantile(t.cpu, 0.99) - cpu_overhead) * 1e6);
}

// FNV-1a over the bytes of the commanded joint references: whether a change to the libraries
// changed a controller's results
inline void Fingerprint(const shm::CommandBlock& c, int njoint, uint64_t* h) {
  for (int j = 0; j < njoint; ++j) {
    unsigned char b[sizeof(double)];
    std::memcpy(b, &c.joint[j].q_ref, sizeof b);
    for (unsigned char x : b) *h = (*h ^ x) * 1099511628211ull;
  }
}

}  // namespace ohrp::bench
