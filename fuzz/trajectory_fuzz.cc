// Fuzzes the trajectory reader (controllers: ParseTrajectory) and the sampling of what it
// accepts: strictly increasing finite times, rows of the same width, interpolation that stays
// finite and within each joint's range of values (found: it overflowed between huge values,
// corpus/trajectory/huge_values.dat), slopes that are never NaN.
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "controllers/trajectory.h"

namespace ctl = ohrp::controllers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  ctl::Trajectory t;
  const ctl::ConfigStatus status = ctl::ParseTrajectory(in, "fuzz.dat", &t);
  if (!status.ok()) {
    if (status.message.empty()) std::abort();
    return 0;
  }
  // the shape and the order it promises
  if (t.rows() == 0 || t.njoint < 0 || t.values.size() != t.rows() * t.njoint ||
      t.line.size() != t.rows()) {
    std::abort();
  }
  for (size_t i = 0; i < t.rows(); ++i) {
    if (!std::isfinite(t.time[i]) || (i > 0 && !(t.time[i] > t.time[i - 1]))) std::abort();
  }
  // samples before, inside and after the rows stay within each joint's values
  std::vector<double> lo(t.njoint, INFINITY), hi(t.njoint, -INFINITY);
  for (size_t i = 0; i < t.rows(); ++i) {
    for (int j = 0; j < t.njoint; ++j) {
      lo[j] = std::min(lo[j], t.row(i)[j]);
      hi[j] = std::max(hi[j], t.row(i)[j]);
    }
  }
  std::vector<double> q(t.njoint), dq(t.njoint);
  const double span = t.duration();
  for (double s : {-1.0, 0.0, 0.37, 0.5, 1.0, 2.0}) {
    const double at = t.start_time() + s * span;
    ctl::SampleTrajectory(t, at, q.data());
    ctl::SampleSlope(t, at, dq.data());
    for (int j = 0; j < t.njoint; ++j) {
      // within the joint's values but for rounding (a few units in the last place)
      const double tol = 8 * DBL_EPSILON * std::max(std::fabs(lo[j]), std::fabs(hi[j]));
      if (!std::isfinite(q[j]) || q[j] < lo[j] - tol || q[j] > hi[j] + tol) std::abort();
      if (std::isnan(dq[j])) std::abort();
    }
  }
  return 0;
}
