// Tests the wake-up lateness histogram: bin bounds, percentiles against exact values, merge.
#include "hw_driver/lateness.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ohrp::hw {
namespace {

TEST(LatenessHistogram, BinsCoverEveryValueAndAreAtMostThreePercentWide) {
  for (int64_t v : {0LL, 1LL, 31LL, 32LL, 33LL, 1000LL, 12345LL, 999999LL, 123456789LL}) {
    const int b = LatenessHistogram::BinOf(v);
    EXPECT_LE(LatenessHistogram::BinLow(b), v) << v;
    EXPECT_GT(LatenessHistogram::BinHigh(b), v) << v;
    if (v >= 32) {
      EXPECT_LE(static_cast<double>(LatenessHistogram::BinHigh(b) - LatenessHistogram::BinLow(b)),
                v / 32.0 + 1e-9)
          << v;
    }
  }
  EXPECT_EQ(LatenessHistogram::BinOf(-5), 0);
  EXPECT_EQ(LatenessHistogram::BinOf(int64_t{1} << 60), LatenessHistogram::kBins - 1);
}

TEST(LatenessHistogram, PercentilesOfAUniformSetAreWithinTheBinWidth) {
  LatenessHistogram h;
  // 1..100000 ns: the p-th percentile is p * 1000 ns
  for (int64_t v = 1; v <= 100000; ++v) h.Add(v);
  EXPECT_EQ(h.count(), 100000u);
  EXPECT_EQ(h.max_ns(), 100000);
  EXPECT_NEAR(h.mean_ns(), 50000.5, 1e-6);
  for (double p : {10.0, 50.0, 90.0, 99.0}) {
    EXPECT_NEAR(h.Percentile(p), p * 1000.0, p * 1000.0 * 0.035) << p;
  }
  EXPECT_LE(h.Percentile(100), 100000.0);
}

TEST(LatenessHistogram, EmptyReadsZeroAndMergeAddsCounts) {
  LatenessHistogram a, b;
  EXPECT_EQ(a.Percentile(50), 0.0);
  a.Add(1000);
  b.Add(3000);
  b.Add(5000);
  a.Merge(b);
  EXPECT_EQ(a.count(), 3u);
  EXPECT_EQ(a.max_ns(), 5000);
  EXPECT_NEAR(a.Percentile(50), 3000, 3000 * 0.035);
  uint64_t total = 0;
  for (const auto& o : a.Octaves()) total += o.count;
  EXPECT_EQ(total, 3u);
  a.Reset();
  EXPECT_EQ(a.count(), 0u);
}

}  // namespace
}  // namespace ohrp::hw
