// Min/max decimation of the viewer's plots (tools/view/include/view/decimate.h): every sample's
// value range is kept per bucket, one-row spikes included, in time order, within the points asked.
#include "view/decimate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ohrp::view {
namespace {

TEST(Decimate, BucketsCoverEveryRowWithinThePointsAsked) {
  for (size_t rows : {1u, 2u, 799u, 800u, 801u, 4001u, 123457u}) {
    const auto b = Buckets(rows, 800);
    EXPECT_LE(2 * b.size(), 800u) << rows;
    EXPECT_EQ(b.front().first, 0u);
    EXPECT_EQ(b.back().second, rows);
    for (size_t i = 1; i < b.size(); ++i) EXPECT_EQ(b[i].first, b[i - 1].second);
  }
}

// random noise with one-row spikes up and down: each bucket's drawn extremes are its true ones,
// so the plotted maximum and minimum are the series' own, at their rows
TEST(Decimate, EverySpikeIsKeptAtItsRow) {
  std::mt19937 gen(7);
  std::normal_distribution<double> noise(300, 5);
  std::vector<double> y(40001);
  for (double& v : y) v = noise(gen);
  y[12345] = 2000;  // an impact
  y[30001] = -50;   // a dip
  y[7] = NAN;       // a missing sample
  const auto buckets = Buckets(y.size(), 800);
  const std::vector<size_t> rows = MinMaxRows(y, buckets);
  EXPECT_LE(rows.size(), 800u);
  for (size_t i = 1; i < rows.size(); ++i) EXPECT_LT(rows[i - 1], rows[i]) << "not in time order";
  EXPECT_NE(std::find(rows.begin(), rows.end(), 12345u), rows.end());
  EXPECT_NE(std::find(rows.begin(), rows.end(), 30001u), rows.end());
  // each bucket's kept rows hold its minimum and maximum
  size_t k = 0;
  for (const auto& [b, e] : buckets) {
    double lo = INFINITY, hi = -INFINITY;
    for (size_t r = b; r < e; ++r)
      if (!std::isnan(y[r])) lo = std::min(lo, y[r]), hi = std::max(hi, y[r]);
    double klo = INFINITY, khi = -INFINITY;
    for (; k < rows.size() && rows[k] < e; ++k) klo = std::min(klo, y[rows[k]]), khi = std::max(khi, y[rows[k]]);
    EXPECT_EQ(klo, lo);
    EXPECT_EQ(khi, hi);
  }
}

}  // namespace
}  // namespace ohrp::view
