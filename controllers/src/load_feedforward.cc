#include "controllers/load_feedforward.h"

#include <algorithm>
#include <cmath>

namespace ohrp::controllers {

LoadFeedforward::LoadFeedforward(const model::Kinematics& k, const int sole[2])
    : sole_{sole[0], sole[1]}, tau_(k.nv()), J_(6, k.nv()) {}

void LoadFeedforward::Compute(model::Kinematics& k, const double share[2], const double* tau_max,
                              double* tau_ff) noexcept {
  const double weight = -k.m()->opt.gravity[2] * k.mass();  // [N], up is +z
  k.GravityTorques(tau_);
  for (int i = 0; i < 2; ++i) {
    const double s = std::isfinite(share[i]) ? std::clamp(share[i], 0.0, 1.0) : 0.0;
    if (s <= 0) continue;
    const model::SoleMap& sole = k.soles()[sole_[i]];
    k.J_WBodyPoint(sole.body_id, k.p_WSole(sole_[i]), J_);
    tau_.noalias() -= J_.row(2).transpose() * (s * weight);
  }
  const int b = k.base_columns();
  for (int j = 0; j < k.njoint(); ++j) {
    const double limit = kLimitShare * tau_max[j];
    const double t = tau_[b + j];
    tau_ff[j] = std::isfinite(t) ? std::clamp(t, -limit, limit) : 0.0;
  }
}

}  // namespace ohrp::controllers
