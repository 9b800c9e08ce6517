// The minimum-jerk ramp.
#include "controllers/ramp.h"

#include <algorithm>

namespace ohrp::controllers {

double MinimumJerk(double u) noexcept {
  if (!(u > 0.0)) return 0.0;  // also catches NaN
  if (u >= 1.0) return 1.0;
  return u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
}

double MinimumJerkRate(double u) noexcept {
  if (!(u > 0.0) || u >= 1.0) return 0.0;
  const double v = u * (1.0 - u);
  return 30.0 * v * v;
}

void SampleRamp(const double* from, const double* to, int n, double elapsed, double duration,
                double* q, double* dq) noexcept {
  double s = 1.0;
  double rate = 0.0;  // ds/dt [1/s]
  if (duration > 0.0) {
    const double u = elapsed / duration;
    s = MinimumJerk(u);
    rate = MinimumJerkRate(u) / duration;
  }
  for (int j = 0; j < n; ++j) {
    const double delta = to[j] - from[j];
    q[j] = from[j] + delta * s;
    if (dq != nullptr) dq[j] = delta * rate;
  }
}

}  // namespace ohrp::controllers
