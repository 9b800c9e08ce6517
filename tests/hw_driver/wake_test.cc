// Tests the spin-tail wake-up (wake.h) against a fake clock and sleeper: the learned margin
// converges to a high quantile of the sleep lateness, stays within its bounds, reacts to a jump
// of the lateness, and the waits end at their deadlines at the cost the Waker counts.
#include "hw_driver/wake.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <stdexcept>

namespace ohrp::hw {
namespace {

constexpr int64_t kUs = 1000;          // [ns]
constexpr int64_t kPeriod = 1000 * kUs;  // 1 ms [ns]
constexpr int64_t kTick = 20;          // [ns] a clock read advances the fake time by this

// a clock whose sleeps wake `lateness()` after their target, and whose reads take kTick
class FakeClock final : public WakeClock {
 public:
  explicit FakeClock(std::function<int64_t()> lateness) : lateness_(std::move(lateness)) {}
  int64_t Now() noexcept override { return t_ += kTick; }
  void SleepUntil(int64_t t) noexcept override {
    ++sleeps_;
    t_ = std::max(t_, t) + lateness_();
  }
  void set_lateness(std::function<int64_t()> f) { lateness_ = std::move(f); }
  int64_t sleeps() const { return sleeps_; }

 private:
  std::function<int64_t()> lateness_;
  int64_t t_ = 0;
  int64_t sleeps_ = 0;
};

// a reproducible lateness uniform in [lo, hi] [ns]
std::function<int64_t()> Uniform(int64_t lo, int64_t hi) {
  return [lo, hi, state = uint64_t{12345}]() mutable {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + static_cast<int64_t>((state >> 33) % static_cast<uint64_t>(hi - lo + 1));
  };
}

std::function<int64_t()> Constant(int64_t v) {
  return [v] { return v; };
}

// runs `n` periodic waits; returns how many woke later than `slack` after their deadline
int RunCycles(Waker* w, int n, int64_t* deadline, int64_t slack = 2 * kTick) {
  int late = 0;
  for (int i = 0; i < n; ++i) {
    *deadline += kPeriod;
    const int64_t woke = w->WaitUntil(*deadline);
    EXPECT_GE(woke, *deadline);
    if (woke - *deadline > slack) ++late;
  }
  return late;
}

TEST(Waker, MarginConvergesToAHighQuantileOfTheSleepLatenessAndTheWakesAreOnTime) {
  FakeClock clock(Uniform(40 * kUs, 60 * kUs));
  Waker w(WakeOptions{}, kPeriod, &clock);
  int64_t deadline = 0;
  RunCycles(&w, 5000, &deadline);
  // the 99.8 % quantile is 59.96 us; the pad 3 us; the step's sawtooth about an eighth above
  const uint64_t spin_before = static_cast<uint64_t>(w.spin_ns());
  const int late = RunCycles(&w, 10000, &deadline);
  EXPECT_GE(w.margin_ns(), 60 * kUs);
  EXPECT_LE(w.margin_ns(), 75 * kUs);
  EXPECT_LE(late, 10000 * 0.005) << "more than 0.5 % of the waits were late";
  // the cost: the spin lasts the margin minus the sleep's lateness, about 10-25 us a cycle
  const double spin_per_cycle = static_cast<double>(w.spin_ns() - spin_before) / 10000;
  EXPECT_GT(spin_per_cycle, 5.0 * kUs);
  EXPECT_LT(spin_per_cycle, 30.0 * kUs);
}

TEST(Waker, MarginStaysWithinItsBounds) {
  // a sleep 5 ms late: the margin stops at the bound, the waits are late, nothing spins forever
  FakeClock slow(Constant(5000 * kUs));
  Waker w(WakeOptions{}, kPeriod, &slow);
  int64_t deadline = 0;
  RunCycles(&w, 2000, &deadline);
  EXPECT_EQ(w.margin_ns(), 200 * kUs);
  EXPECT_GT(slow.sleeps(), 0);
  EXPECT_EQ(w.overslept(), static_cast<uint64_t>(slow.sleeps()));  // every sleep woke too late
  // the bound is at most a quarter of a short period
  FakeClock slow2(Constant(5000 * kUs));
  Waker short_period(WakeOptions{}, 100 * kUs, &slow2);
  short_period.WaitUntil(100 * kUs);
  EXPECT_LE(short_period.margin_ns(), 25 * kUs);
  // a sleep that is never late: the margin comes down to the pad, not below the minimum
  FakeClock exact(Constant(0));
  WakeOptions o;
  o.min_margin = 5e-6;
  Waker w2(o, kPeriod, &exact);
  deadline = 0;
  RunCycles(&w2, 20000, &deadline);
  EXPECT_EQ(w2.margin_ns(), 5 * kUs);
}

TEST(Waker, MarginRisesWithinAFewCyclesOfAJumpInLatenessAndComesBackSlowly) {
  FakeClock clock(Constant(50 * kUs));
  Waker w(WakeOptions{}, kPeriod, &clock);
  int64_t deadline = 0;
  RunCycles(&w, 5000, &deadline);
  EXPECT_LT(w.margin_ns(), 65 * kUs);
  // the jump: late wakes only while the margin climbs, an eighth at a time
  clock.set_lateness(Constant(150 * kUs));
  const int late = RunCycles(&w, 100, &deadline);
  EXPECT_GE(w.margin_ns(), 150 * kUs);
  EXPECT_LE(late, 15);
  EXPECT_EQ(RunCycles(&w, 1000, &deadline), 0);
  // back to 50 us: no late wake while it comes down, and down it comes
  clock.set_lateness(Constant(50 * kUs));
  EXPECT_EQ(RunCycles(&w, 20000, &deadline), 0);
  EXPECT_LT(w.margin_ns(), 80 * kUs);
}

TEST(Waker, SleepModeSleepsToTheDeadlineAndNeverSpins) {
  FakeClock clock(Constant(50 * kUs));
  WakeOptions o;
  o.mode = WakeMode::kSleep;
  Waker w(o, kPeriod, &clock);
  const int64_t woke = w.WaitUntil(kPeriod);
  EXPECT_GE(woke, kPeriod + 50 * kUs);
  EXPECT_EQ(w.spin_ns(), 0);
  EXPECT_EQ(clock.sleeps(), 1);
}

TEST(Waker, ADeadlineAlreadyPastReturnsAtOnce) {
  FakeClock clock(Constant(0));
  Waker w(WakeOptions{}, kPeriod, &clock);
  clock.SleepUntil(10 * kPeriod);
  const int64_t sleeps = clock.sleeps();
  EXPECT_GE(w.WaitUntil(kPeriod), 10 * kPeriod);
  EXPECT_EQ(clock.sleeps(), sleeps);
}

TEST(MarginLearner, RefusesBadBoundsAndQuantilesNamingThem) {
  EXPECT_THROW(
      {
        try {
          MarginLearner(0.998, 0, 0, 10, 5);
        } catch (const std::invalid_argument& e) {
          EXPECT_NE(std::string(e.what()).find("min <= max"), std::string::npos) << e.what();
          throw;
        }
      },
      std::invalid_argument);
  EXPECT_THROW(MarginLearner(1.0, 0, 0, 0, 5), std::invalid_argument);
  EXPECT_THROW(MarginLearner(0.2, 0, 0, 0, 5), std::invalid_argument);
}

TEST(WakeMode, NamesParseBack) {
  for (WakeMode m : {WakeMode::kSleep, WakeMode::kSpinTail}) {
    WakeMode parsed = m == WakeMode::kSleep ? WakeMode::kSpinTail : WakeMode::kSleep;
    ASSERT_TRUE(ParseWakeMode(WakeModeName(m), &parsed));
    EXPECT_EQ(parsed, m);
  }
  WakeMode untouched = WakeMode::kSleep;
  EXPECT_FALSE(ParseWakeMode("spin", &untouched));
  EXPECT_EQ(untouched, WakeMode::kSleep);
}

}  // namespace
}  // namespace ohrp::hw
