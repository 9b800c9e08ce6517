// Min/max decimation of the plots' curves: a long series is cut into buckets of consecutive
// samples, and each bucket is drawn by its smallest and its largest sample, in time order, so
// that every peak (an impact's one-sample spike included) is kept at its value; taking every
// N-th row lost them. A bucket of one sample gives that sample.
#pragma once

#include <cmath>
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace ohrp::view {

// the [begin, end) rows of each bucket when `rows` samples are drawn by at most `points` points
// (two per bucket)
inline std::vector<std::pair<size_t, size_t>> Buckets(size_t rows, size_t points) {
  std::vector<std::pair<size_t, size_t>> out;
  const size_t per = std::max<size_t>(1, (rows + points / 2 - 1) / std::max<size_t>(1, points / 2));
  for (size_t b = 0; b < rows; b += per) out.push_back({b, std::min(rows, b + per)});
  return out;
}

// the rows that draw `y` over `buckets`: per bucket the row of its minimum and the row of its
// maximum, the earlier first (NaN samples are skipped; a bucket of NaN gives its first row)
inline std::vector<size_t> MinMaxRows(const std::vector<double>& y,
                                      const std::vector<std::pair<size_t, size_t>>& buckets) {
  std::vector<size_t> rows;
  for (const auto& [b, e] : buckets) {
    size_t lo = b, hi = b;
    for (size_t r = b; r < e; ++r) {
      if (std::isnan(y[r])) continue;
      if (std::isnan(y[lo]) || y[r] < y[lo]) lo = r;
      if (std::isnan(y[hi]) || y[r] > y[hi]) hi = r;
    }
    rows.push_back(std::min(lo, hi));
    if (lo != hi) rows.push_back(std::max(lo, hi));
  }
  return rows;
}

}  // namespace ohrp::view
