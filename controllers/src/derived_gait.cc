#include "controllers/derived_gait.h"

#include <algorithm>
#include <cmath>

namespace ohrp::controllers {

DerivedGait ScaleGait(double leg, double anchor_leg, double stride, double step_height,
                      double step_time) {
  DerivedGait d;
  d.ratio = leg / anchor_leg;
  if (std::abs(d.ratio - 1) <= kSameLeg) d.ratio = 1;
  d.max_forward = stride * d.ratio;          // lengths in leg lengths
  d.step_height = step_height * d.ratio;
  d.step_time = step_time * std::sqrt(d.ratio);  // times in sqrt(L / g)
  return d;
}

SagEstimate LargestSag(const int* leg, int n, const double* tau, const double* kp) {
  SagEstimate s;
  for (int i = 0; i < n; ++i) {
    const int j = leg[i];
    if (!(kp[j] > 0)) continue;
    const double sag = std::abs(tau[j]) / kp[j];
    if (s.joint < 0 || sag > s.sag) s = {sag, j, tau[j], kp[j]};
  }
  return s;
}

double AnkleDamping(double kp, double default_d, double time_constant) {
  if (!(kp > 0) || !std::isfinite(kp)) return default_d;
  return std::min(default_d, kp * time_constant);
}

double CompliantStride(double stride, double leg, double sag) {
  if (!(sag > kSagLimit) || !(leg > 0)) return stride;
  return std::max(stride - leg * sag, 0.5 * stride);
}

}  // namespace ohrp::controllers
