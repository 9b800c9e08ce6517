// The benchmarks' order statistics, defined once: the q-quantile of a set of samples is the
// sample at rank floor(q n) of the n sorted samples (the last one at most), and the median is
// the 0.5-quantile (the upper of the two middle samples when n is even).
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace ohrp::bench {

// The `q`-quantile (0 <= q <= 1) of the samples `v` (sorted here, in a copy); 0 when `v` is
// empty.
inline double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

// The median of the samples `v`: Quantile(v, 0.5), the sample at rank n / 2; 0 when empty.
inline double Median(std::vector<double> v) { return Quantile(std::move(v), 0.5); }

}  // namespace ohrp::bench
