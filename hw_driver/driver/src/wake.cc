// Waking on time: the monotonic clock, the learned margin and the spin-tail wait (see wake.h).
#include "hw_driver/wake.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ohrp::hw {
namespace {

constexpr double kStepFraction = 1.0 / 8;  // quantile step: this part of the estimate
constexpr double kMinStep = 250;           // [ns] the step when the estimate is near zero

// tells the CPU this is a spin-wait (lets a sibling hyper-thread run, saves power)
inline void CpuRelax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield" ::: "memory");
#endif
}

// the real clock: CLOCK_MONOTONIC, and an absolute sleep that a signal does not cut short
class Monotonic final : public WakeClock {
 public:
  int64_t Now() noexcept override { return MonotonicNs(); }
  void SleepUntil(int64_t t) noexcept override { SleepUntilNs(t); }
};

int64_t ToNs(double s) { return std::llround(s * 1e9); }

// the margin's upper bound: the options' bound, and never more than its part of the period
int64_t MaxMarginNs(const WakeOptions& o, int64_t period_ns) {
  return std::min<int64_t>(ToNs(o.max_margin),
                           std::llround(o.max_period_fraction * static_cast<double>(period_ns)));
}

}  // namespace

//---------------- clock and modes ----------------

WakeClock& MonotonicClock() {
  static Monotonic clock;
  return clock;
}

const char* WakeModeName(WakeMode m) {
  return m == WakeMode::kSleep ? "sleep" : "spin-tail";
}

bool ParseWakeMode(const std::string& s, WakeMode* out) {
  if (s == "sleep") {
    *out = WakeMode::kSleep;
  } else if (s == "spin-tail") {
    *out = WakeMode::kSpinTail;
  } else {
    return false;
  }
  return true;
}

//---------------- the learned margin ----------------

MarginLearner::MarginLearner(double quantile, int64_t pad_ns, int64_t initial_ns, int64_t min_ns,
                             int64_t max_ns)
    : quantile_(quantile), pad_(static_cast<double>(pad_ns)), min_(min_ns), max_(max_ns) {
  if (!(quantile >= 0.5 && quantile < 1.0)) {
    throw std::invalid_argument("MarginLearner: quantile must be in [0.5, 1), got " +
                                std::to_string(quantile));
  }
  if (min_ns < 0 || min_ns > max_ns) {
    throw std::invalid_argument("MarginLearner: need 0 <= min <= max, got min " +
                                std::to_string(min_ns) + " ns, max " + std::to_string(max_ns) +
                                " ns");
  }
  // the estimate starts where the initial margin puts it
  estimate_ = std::max(0.0, static_cast<double>(initial_ns) - pad_);
  Update();
}

void MarginLearner::Observe(int64_t lateness_ns) noexcept {
  const double x = static_cast<double>(std::max<int64_t>(0, lateness_ns));
  // a step proportional to the estimate: fast up after a jump, slow down, scale-free
  const double step = std::max(kMinStep, estimate_ * kStepFraction);
  if (x > estimate_) {
    estimate_ += step * quantile_;
  } else {
    estimate_ = std::max(0.0, estimate_ - step * (1.0 - quantile_));
  }
  // keep the estimate within reach of the bounds, so it comes back fast from either end
  estimate_ = std::min(estimate_, 2.0 * static_cast<double>(max_));
  Update();
}

void MarginLearner::Update() noexcept {
  const double m = std::clamp(estimate_ + pad_, static_cast<double>(min_),
                              static_cast<double>(max_));
  margin_ = std::llround(m);
}

//---------------- the wait ----------------

Waker::Waker(const WakeOptions& o, int64_t period_ns, WakeClock* clock)
    : mode_(o.mode),
      clock_(clock),
      learner_(o.quantile, ToNs(o.pad), std::min<int64_t>(ToNs(o.initial_margin), MaxMarginNs(o, period_ns)),
               ToNs(o.min_margin), MaxMarginNs(o, period_ns)) {
  if (period_ns <= 0) throw std::invalid_argument("Waker: period must be > 0 ns");
}

int64_t Waker::WaitUntil(int64_t deadline) noexcept {
  ++waits_;
  if (mode_ == WakeMode::kSleep) {
    clock_->SleepUntil(deadline);
    return clock_->Now();
  }
  // sleep short of the deadline by the margin, and learn from how late that sleep woke
  const int64_t target = deadline - learner_.margin_ns();
  int64_t now = clock_->Now();
  if (now < target) {
    clock_->SleepUntil(target);
    now = clock_->Now();
    learner_.Observe(now - target);
    if (now > deadline) ++overslept_;
  }
  if (now >= deadline) return now;
  // spin on the clock for the rest
  const int64_t spin_start = now;
  while (now < deadline) {
    CpuRelax();
    now = clock_->Now();
  }
  spin_ns_ += now - spin_start;
  return now;
}

}  // namespace ohrp::hw
