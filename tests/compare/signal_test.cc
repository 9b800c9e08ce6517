// The comparison's signal helpers against closed forms: the lag of a shifted damped
// oscillation by cross-correlation, the noise level, and the frequency and decay of a damped
// oscillation with and without noise and offset.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "compare/oscillation.h"
#include "compare/signal.h"
#include "synthetic.h"

namespace ohrp::compare {
namespace {

using testing::Damped;
using testing::Noise;

// samples of f at t0, t0 + h, ... <= t1, plus noise
template <class F>
void Sample(F f, double t0, double t1, double h, double noise_sd, unsigned seed,
            std::vector<double>* t, std::vector<double>* x) {
  Noise n(noise_sd, seed);
  t->clear();
  x->clear();
  for (int k = 0; t0 + k * h <= t1 + 1e-12; ++k) {
    t->push_back(t0 + k * h);
    x->push_back(f(t->back()) + n());
  }
}

TEST(Signal, InterpolateIsLinearBetweenSamplesAndClampedOutside) {
  const std::vector<double> t = {0, 1, 3}, x = {0, 2, 6};
  size_t c = 0;
  EXPECT_DOUBLE_EQ(Interpolate(t, x, 0.5, &c), 1.0);
  EXPECT_DOUBLE_EQ(Interpolate(t, x, 2.0, &c), 4.0);
  EXPECT_DOUBLE_EQ(Interpolate(t, x, 0.25, &c), 0.5);  // backwards after a later look-up
  EXPECT_DOUBLE_EQ(Interpolate(t, x, -1, &c), 0.0);
  EXPECT_DOUBLE_EQ(Interpolate(t, x, 9, &c), 6.0);
  EXPECT_DOUBLE_EQ(MedianStep(t), 2.0);
}

// B is A delayed by 0.137 s, sampled at another rate from another start, with noise of 2 % of
// the amplitude: the lag is found within 1 ms (less than half of either sample step)
TEST(Signal, CrossCorrelationFindsTheLagOfAShiftedNoisyDampedOscillation) {
  const Damped d;
  const double lag = 0.137;
  std::vector<double> ta, xa, tb, xb;
  Sample(d, 0.0, 10.0, 0.002, 0.0, 1, &ta, &xa);
  Sample([&](double t) { return d(t - lag); }, 0.0013, 10.5, 0.0025, 0.02, 2, &tb, &xb);
  double found = 0;
  std::string error;
  ASSERT_TRUE(CrossCorrelationLag(ta, xa, tb, xb, 0.0, 2.0, &found, &error)) << error;
  EXPECT_NEAR(found, lag, 0.001);
  // and the other way round: A behind B by the same lag
  double back = 0;
  ASSERT_TRUE(CrossCorrelationLag(tb, xb, ta, xa, 0.0, 2.0, &back, &error)) << error;
  EXPECT_NEAR(back, -lag, 0.001);
  std::printf("[ figures  ] lag %.4f s: found %.5f s and %.5f s back\n", lag, found, back);
}

TEST(Signal, CrossCorrelationRefusesAFlatChannelAndAPeakOnTheSearchEdge) {
  const Damped d;
  std::vector<double> ta, xa, tb, xb;
  Sample(d, 0.0, 10.0, 0.002, 0.0, 1, &ta, &xa);
  Sample([](double) { return 1.0; }, 0.0, 10.0, 0.002, 0.0, 1, &tb, &xb);
  double lag = 0;
  std::string error;
  EXPECT_FALSE(CrossCorrelationLag(ta, xa, tb, xb, 0.0, 2.0, &lag, &error));
  EXPECT_NE(error.find("constant"), std::string::npos) << error;
  // a smooth step 1 s later, searched within +-0.3 s: the best lag searched is on the edge
  auto step = [](double t) { return std::tanh((t - 5.0) / 0.2); };
  Sample(step, 0.0, 10.0, 0.002, 0.0, 1, &ta, &xa);
  Sample([&](double t) { return step(t - 1.0); }, 0.0, 10.0, 0.002, 0.0, 1, &tb, &xb);
  EXPECT_FALSE(CrossCorrelationLag(ta, xa, tb, xb, 0.0, 0.3, &lag, &error));
  EXPECT_NE(error.find("max-lag"), std::string::npos) << error;
}

TEST(Signal, NoiseSigmaRecoversTheNoiseOnASmoothSignal) {
  const Damped d;
  std::vector<double> t, x;
  Sample(d, 0.0, 10.0, 0.002, 0.01, 7, &t, &x);
  EXPECT_NEAR(NoiseSigma(x), 0.01, 0.001);
}

// f_d, sigma and the log decrement of x(t) = c + A exp(-sigma t) sin(omega_d t) are the closed
// form's: exactly (to the sampling) without noise, within a few per cent with noise
TEST(Oscillation, FrequencyAndDecayOfADampedSineAreTheClosedForm) {
  Damped d;
  d.c = 3.0;  // an offset changes nothing
  std::vector<double> t, x;
  Sample(d, 0.0, 10.0, 0.002, 0.0, 1, &t, &x);
  const Oscillation o = AnalyseOscillation(t, x, 2.0, 10.0);
  ASSERT_TRUE(o.found) << o.why;
  EXPECT_NEAR(o.frequency, d.f_d, 1e-3 * d.f_d);
  EXPECT_NEAR(o.log_decrement, d.log_decrement(), 0.01 * d.log_decrement());
  EXPECT_NEAR(o.damping_ratio, d.zeta, 0.01 * d.zeta);
  EXPECT_NEAR(o.decay_ratio, std::exp(-d.log_decrement()), 0.005);
  EXPECT_NEAR(o.natural_frequency, d.f_d / std::sqrt(1 - d.zeta * d.zeta), 1e-3 * d.f_d);
  EXPECT_GE(o.extrema, 10);
  std::printf("[ figures  ] clean: f %.5f Hz (%.5f), delta %.5f (%.5f), zeta %.5f, %d extrema\n",
              o.frequency, d.f_d, o.log_decrement, d.log_decrement(), o.damping_ratio, o.extrema);
}

TEST(Oscillation, WithNoiseTheFiguresStayWithinTheirStandardErrorsAndAFewPerCent) {
  Damped d;
  d.f_d = 1.3;
  d.zeta = 0.08;
  std::vector<double> t, x;
  Sample(d, 0.0, 12.0, 0.002, 0.02, 11, &t, &x);
  const Oscillation o = AnalyseOscillation(t, x, 2.0, 12.0);
  ASSERT_TRUE(o.found) << o.why;
  EXPECT_NEAR(o.frequency, d.f_d, 0.01 * d.f_d);
  EXPECT_NEAR(o.log_decrement, d.log_decrement(), 0.05 * d.log_decrement());
  EXPECT_LT(std::fabs(o.frequency - d.f_d), 4 * o.frequency_se + 1e-4);
  EXPECT_LT(std::fabs(o.log_decrement - d.log_decrement()), 4 * o.log_decrement_se + 1e-3);
  EXPECT_NEAR(o.noise, 0.02, 0.003);
  std::printf("[ figures  ] noisy: f %.5f +- %.5f Hz (%.5f), delta %.5f +- %.5f (%.5f), %d extrema\n",
              o.frequency, o.frequency_se, d.f_d, o.log_decrement, o.log_decrement_se,
              d.log_decrement(), o.extrema);
}

// a strongly damped oscillation whose swings sink into the noise within the window (the rocking
// of docs/identify.md: 2.45 Hz, delta 0.72, first swing 100 noise sigma): over 40 draws of the
// noise the decay stays near the closed form, however many tail swings a draw lets through
// (weighted by their noise, the tail's kept above 16 sigma; unweighted and above 8 sigma, draws
// came out up to 20 % low)
TEST(Oscillation, TheDecayDoesNotHangOnTheSwingsAtTheNoise) {
  Damped d;
  d.f_d = 2.45;
  d.zeta = 0.114;
  std::vector<double> t, x, deltas;
  for (unsigned seed = 1; seed <= 40; ++seed) {
    Sample(d, 0.0, 5.5, 0.002, 0.01, seed, &t, &x);
    const Oscillation o = AnalyseOscillation(t, x, 2.1, 5.1);
    ASSERT_TRUE(o.found) << o.why << ", seed " << seed;
    deltas.push_back(o.log_decrement);
  }
  double mean = 0, worst = 0;
  for (double v : deltas) {
    mean += v / static_cast<double>(deltas.size());
    worst = std::max(worst, std::fabs(v / d.log_decrement() - 1));
  }
  EXPECT_NEAR(mean, d.log_decrement(), 0.02 * d.log_decrement());
  EXPECT_LT(worst, 0.06);
  std::printf("[ figures  ] rocking-like, 40 noise draws: delta mean %.4f (closed form %.4f), worst "
              "%.1f %% off\n", mean, d.log_decrement(), 100 * worst);
}

TEST(Oscillation, NoiseAloneIsNoOscillation) {
  std::vector<double> t, x;
  Sample([](double) { return 0.0; }, 0.0, 5.0, 0.002, 0.02, 5, &t, &x);
  const Oscillation o = AnalyseOscillation(t, x, 0.0, 5.0);
  EXPECT_FALSE(o.found);
  EXPECT_FALSE(o.why.empty());
}

// issue 35: soles damped heavily (damping ratio 0.18 to 0.45) leave two or three swings above
// the noise, too few for the extrema; the damped sine fitted to the window recovers the closed
// form's frequency and decay, over 10 draws of noise at 2 % of the first swing each
TEST(Oscillation, AHeavilyDampedOscillationIsMeasuredByTheFit) {
  for (const double zeta : {0.18, 0.3, 0.45}) {
    Damped d;
    d.f_d = 2.45;
    d.zeta = zeta;
    double worst_f = 0, worst_delta = 0, mean_delta = 0;
    int within_se = 0;
    for (unsigned seed = 1; seed <= 10; ++seed) {
      std::vector<double> t, x;
      Sample(d, 0.0, 5.0, 0.002, 0.02, seed, &t, &x);
      const Oscillation o = AnalyseOscillation(t, x, 2.0, 5.0);
      ASSERT_TRUE(o.found) << "zeta " << zeta << ", seed " << seed << ": " << o.why;
      worst_f = std::max(worst_f, std::fabs(o.frequency / d.f_d - 1));
      worst_delta = std::max(worst_delta, std::fabs(o.log_decrement / d.log_decrement() - 1));
      mean_delta += o.log_decrement / 10;
      if (std::fabs(o.log_decrement - d.log_decrement()) < 3 * o.log_decrement_se) ++within_se;
      if (zeta > 0.25) {
        EXPECT_EQ(o.method, "fit") << zeta;
      }
    }
    EXPECT_LT(worst_f, 0.02) << zeta;
    EXPECT_LT(worst_delta, 0.08) << zeta;
    EXPECT_NEAR(mean_delta, d.log_decrement(), 0.03 * d.log_decrement()) << zeta;
    if (zeta > 0.25) {
      EXPECT_GE(within_se, 8) << zeta;  // the fit's standard errors cover the spread
    }
    std::printf("[ figures  ] zeta %.2f: delta mean %.4f (closed form %.4f), worst %.1f %%; f worst "
                "%.2f %%; %d of 10 within 3 standard errors\n",
                zeta, mean_delta, d.log_decrement(), 100 * worst_delta, 100 * worst_f, within_se);
  }
}

}  // namespace
}  // namespace ohrp::compare
