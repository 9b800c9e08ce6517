// Tests parameters drawn at random (tools/sweep/src/draw.cc): the draws' mean and spread against
// the distribution's closed forms, the clip, the same seed giving the same draws, a zip of draws
// as one axis, and the refusals.
#include <gtest/gtest.h>

#include <cmath>

#include "sweep/sweep.h"

namespace ohrp::sweep {
namespace {

const std::string kSource = OHRP_SOURCE_DIR;
const std::string kPath = kSource + "/tests/sweep/in_memory.yaml";

bool Parse(const std::string& draw, SweepSpec* s, std::string* error) {
  return ParseSweep("scenario: stand_short.yaml\nparameters:\n"
                    "  - {key: contact_params.damping, draw: " + draw + "}\n", kPath, kSource, s, error);
}

void Moments(const Parameter& p, double* mean, double* std, double* lo, double* hi) {
  double s = 0, s2 = 0;
  *lo = 1e300, *hi = -1e300;
  for (const Value& v : p.values) s += v.number, *lo = std::fmin(*lo, v.number), *hi = std::fmax(*hi, v.number);
  *mean = s / p.values.size();
  for (const Value& v : p.values) s2 += (v.number - *mean) * (v.number - *mean);
  *std = std::sqrt(s2 / (p.values.size() - 1));
}

TEST(SweepDraws, UniformHasItsMeanAndSpread) {
  SweepSpec s;
  std::string error;
  ASSERT_TRUE(Parse("{distribution: uniform, from: 20, to: 60, n: 4000, seed: 3}", &s, &error)) << error;
  ASSERT_EQ(s.variants.size(), 4000u);
  double mean, std, lo, hi;
  Moments(s.parameters[0], &mean, &std, &lo, &hi);
  // uniform [a, b): mean (a + b) / 2, std (b - a) / sqrt 12; the mean within 4 standard errors
  const double sd = 40 / std::sqrt(12.0);
  EXPECT_NEAR(mean, 40, 4 * sd / std::sqrt(4000.0));
  EXPECT_NEAR(std, sd, 4 * sd / std::sqrt(2 * 4000.0));
  EXPECT_GE(lo, 20);
  EXPECT_LT(hi, 60);
  EXPECT_NE(s.parameters[0].draw.find("seed 3"), std::string::npos) << s.parameters[0].draw;
}

TEST(SweepDraws, ClippedNormalStaysInsideAndKeepsItsShape) {
  SweepSpec s;
  std::string error;
  ASSERT_TRUE(Parse("{distribution: normal, mean: 1.5, std: 0.2, clip: [1.1, 1.9], n: 4000, seed: 5}",
                    &s, &error)) << error;
  double mean, std, lo, hi;
  Moments(s.parameters[0], &mean, &std, &lo, &hi);
  EXPECT_GE(lo, 1.1);
  EXPECT_LE(hi, 1.9);
  // truncated at +-2 sigma (redrawn): mean 1.5 by symmetry; std sigma sqrt(1 - 2 a phi(a) /
  // (2 Phi(a) - 1)) with a = 2: 0.2 x 0.8796 = 0.1759
  const double a = 2, phi = std::exp(-a * a / 2) / std::sqrt(2 * M_PI), Z = std::erf(a / std::sqrt(2.0));
  const double truncated = 0.2 * std::sqrt(1 - 2 * a * phi / Z);
  EXPECT_NEAR(mean, 1.5, 4 * truncated / std::sqrt(4000.0));
  EXPECT_NEAR(std, truncated, 4 * truncated / std::sqrt(2 * 4000.0));
}

TEST(SweepDraws, TheSameSeedGivesTheSameDrawsAnotherOthers) {
  SweepSpec a, b, c;
  std::string error;
  ASSERT_TRUE(Parse("{distribution: normal, mean: 30, std: 5, n: 8, seed: 7}", &a, &error));
  ASSERT_TRUE(Parse("{distribution: normal, mean: 30, std: 5, n: 8, seed: 7}", &b, &error));
  ASSERT_TRUE(Parse("{distribution: normal, mean: 30, std: 5, n: 8, seed: 8}", &c, &error));
  for (int i = 0; i < 8; ++i) {
    EXPECT_EQ(a.parameters[0].values[i].text, b.parameters[0].values[i].text);
    EXPECT_NE(a.parameters[0].values[i].text, c.parameters[0].values[i].text);
  }
}

TEST(SweepDraws, ZippedDrawsAreOneAxisAgainstAGrid) {
  SweepSpec s;
  std::string error;
  ASSERT_TRUE(ParseSweep("scenario: stand_short.yaml\nparameters:\n"
                         "  - zip:\n"
                         "      - {key: contact_params.damping, draw: {distribution: uniform, from: 20, to: 60, n: 5, seed: 1}}\n"
                         "      - {key: contact_params.stiffness, draw: {distribution: normal, mean: 2e6, std: 2e5, n: 5, seed: 2}}\n"
                         "  - {key: duration, values: [1.5, 2]}\n", kPath, kSource, &s, &error)) << error;
  EXPECT_EQ(s.variants.size(), 10u);
}

TEST(SweepDraws, BadDrawsAreRefused) {
  const char* bad[][2] = {
      {"{distribution: poisson, n: 3, seed: 1}", "distribution: uniform or normal"},
      {"{distribution: uniform, from: 2, to: 1, n: 3, seed: 1}", "from must be below to"},
      {"{distribution: uniform, from: 1, to: 2, n: 3}", "seed: a non-negative whole number"},
      {"{distribution: normal, mean: 1, std: 0, n: 3, seed: 1}", "std must be above 0"},
      {"{distribution: normal, mean: 1, std: 1, clip: [5, 6], n: 3, seed: 1}", "clip: [LO, HI]"},
      {"{distribution: normal, mean: 1, std: 1, n: 0, seed: 1}", "n: the number of draws"},
      {"{distribution: uniform, from: 1, to: 2, n: 3, seed: 1, mean: 4}", "uniform takes from and to"},
  };
  for (const auto& [draw, expect] : bad) {
    SweepSpec s;
    std::string error;
    EXPECT_FALSE(Parse(draw, &s, &error)) << draw;
    EXPECT_NE(error.find(expect), std::string::npos) << draw << " -> " << error;
  }
}

}  // namespace
}  // namespace ohrp::sweep
