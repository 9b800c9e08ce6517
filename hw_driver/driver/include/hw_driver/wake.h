// Waking a periodic loop on time: the monotonic clock, and the wait for an absolute deadline.
//
// A plain clock_nanosleep(TIMER_ABSTIME) wakes tens of microseconds late on a general-purpose
// kernel (timer slack, the wake-up of an idle CPU, the scheduler). The spin-tail wait sleeps
// until `margin` before the deadline, then spins on the monotonic clock until the deadline:
// it wakes within the clock's read time of the deadline whenever the sleep's own lateness
// stays below the margin. The margin is learned from the sleeps' measured lateness
// (MarginLearner: a running high quantile plus a pad, bounded), so it grows at once when the
// machine gets slower to wake and shrinks slowly when it gets faster; the spinning costs CPU
// time, about (margin - sleep lateness) per cycle, which Waker counts.
//
// Nothing here allocates, throws or logs after construction: WaitUntil runs in the cycle.
// Times are integer nanoseconds on CLOCK_MONOTONIC.
#pragma once

#include <cstdint>
#include <string>

#include "shm_bridge/clock.h"  // MonotonicNs: the one clock of the driver, its benchmark, its tests

namespace ohrp::hw {

// how a loop waits for its deadline
enum class WakeMode {
  kSleep,     // clock_nanosleep(TIMER_ABSTIME) to the deadline: no CPU, tens of us late
  kSpinTail,  // sleep to deadline - learned margin, then spin on the clock (the default)
};
const char* WakeModeName(WakeMode m);  // "sleep" | "spin-tail"
// Parses "sleep" or "spin-tail"; false (and `*out` untouched) otherwise.
bool ParseWakeMode(const std::string& s, WakeMode* out);

struct WakeOptions {
  WakeMode mode = WakeMode::kSpinTail;
  double quantile = 0.998;         // quantile of the sleep lateness the margin tracks (0.5..1)
  double pad = 3e-6;               // [s] added to the quantile
  double initial_margin = 100e-6;  // [s] before anything is learned
  double min_margin = 2e-6;        // [s] lower bound of the margin
  double max_margin = 200e-6;      // [s] upper bound; never above max_period_fraction period
  double max_period_fraction = 0.25;  // the spin never takes more than this part of a period
};

// The time source and sleeper of a Waker. The real one is MonotonicClock(); tests give a fake.
class WakeClock {
 public:
  virtual ~WakeClock() = default;
  virtual int64_t Now() noexcept = 0;                // [ns]
  virtual void SleepUntil(int64_t t_ns) noexcept = 0;  // absolute; returns at t_ns or later
};
// CLOCK_MONOTONIC with clock_nanosleep(TIMER_ABSTIME), retried on EINTR. Shared, stateless.
WakeClock& MonotonicClock();

// A running high quantile of the sleep lateness (stochastic quantile tracking with a step
// proportional to the estimate: a sample above it raises it by about `quantile` / 8 of it, a
// sample below lowers it by (1 - quantile) / 8 of it), plus a pad, clamped to [min, max].
class MarginLearner {
 public:
  // Margins in [ns]; `quantile` in [0.5, 1). Throws std::invalid_argument when
  // min_ns > max_ns, min_ns < 0 or quantile is outside [0.5, 1).
  MarginLearner(double quantile, int64_t pad_ns, int64_t initial_ns, int64_t min_ns,
                int64_t max_ns);

  // Takes one measured sleep lateness [ns] (negative counts as 0).
  void Observe(int64_t lateness_ns) noexcept;
  // The margin to sleep short of the next deadline by [ns], within [min, max].
  int64_t margin_ns() const noexcept { return margin_; }
  // The current quantile estimate of the sleep lateness [ns] (unbounded by min/max).
  double quantile_ns() const noexcept { return estimate_; }

 private:
  void Update() noexcept;
  double quantile_;
  double pad_;
  int64_t min_, max_;
  double estimate_;
  int64_t margin_;
};

// Waits for absolute deadlines of a loop with period `period_ns`, in the chosen mode.
class Waker {
 public:
  // `clock` is not owned and outlives the Waker. Throws std::invalid_argument on options that
  // MarginLearner refuses or a period <= 0.
  Waker(const WakeOptions& options, int64_t period_ns, WakeClock* clock = &MonotonicClock());

  // Returns at `deadline_ns` or later, with the clock's time then [ns]. Real-time safe.
  int64_t WaitUntil(int64_t deadline_ns) noexcept;

  WakeMode mode() const { return mode_; }
  int64_t margin_ns() const { return learner_.margin_ns(); }
  const MarginLearner& learner() const { return learner_; }
  int64_t spin_ns() const { return spin_ns_; }  // total time spent spinning [ns]
  uint64_t waits() const { return waits_; }
  uint64_t overslept() const { return overslept_; }  // sleeps that woke after the deadline

 private:
  WakeMode mode_;
  WakeClock* clock_;
  MarginLearner learner_;
  int64_t spin_ns_ = 0;
  uint64_t waits_ = 0;
  uint64_t overslept_ = 0;
};

}  // namespace ohrp::hw
