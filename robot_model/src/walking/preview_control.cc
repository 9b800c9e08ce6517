// Preview control gains from the discrete Riccati equation, and the servo step (preview_control.h).
#include "walking/preview_control.h"

#include <Eigen/Dense>
#include <cmath>

namespace ohrp::walking {

bool PreviewGains::Compute(const PreviewOptions& o, std::string* error) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(o.dt) || !positive(o.zc) || !positive(o.gravity) || !positive(o.preview_time) ||
      !positive(o.q) || !positive(o.r)) {
    *error = "preview control: dt, zc, gravity, preview_time, q and r must be finite and "
             "positive (got dt " + std::to_string(o.dt) + ", zc " + std::to_string(o.zc) +
             ", preview_time " + std::to_string(o.preview_time) + ")";
    return false;
  }
  const int n = static_cast<int>(std::lround(o.preview_time / o.dt));
  if (n < 1 || n > 100000) {
    *error = "preview control: preview_time / dt gives " + std::to_string(n) +
             " samples; use 1..100000";
    return false;
  }
  options_ = o;
  const double dt = o.dt;
  A_ << 1, dt, dt * dt / 2, 0, 1, dt, 0, 0, 1;
  B_ << dt * dt * dt / 6, dt * dt / 2, dt;
  C_ << 1, 0, -o.zc / o.gravity;

  // the augmented system on (e, dx): X(k+1) = At X(k) + Bt du(k)
  Eigen::Matrix4d At = Eigen::Matrix4d::Zero();
  At(0, 0) = 1;
  At.block<1, 3>(0, 1) = C_ * A_;
  At.block<3, 3>(1, 1) = A_;
  Eigen::Vector4d Bt;
  Bt(0) = C_ * B_;
  Bt.tail<3>() = B_;
  Eigen::Matrix4d Qt = Eigen::Matrix4d::Zero();
  Qt(0, 0) = o.q;
  Eigen::Vector4d It(1, 0, 0, 0);
  Eigen::Matrix<double, 4, 3> Ft;
  Ft.row(0) = C_ * A_;
  Ft.bottomRows<3>() = A_;

  // the Riccati equation by the structure-preserving doubling algorithm: converges
  // quadratically where the plain iteration needs tens of thousands of steps at R = 1e-6
  Eigen::Matrix4d Ak = At;
  Eigen::Matrix4d Gk = Bt * Bt.transpose() / o.r;
  Eigen::Matrix4d Hk = Qt;
  const Eigen::Matrix4d I = Eigen::Matrix4d::Identity();
  bool converged = false;
  for (int it = 0; it < 100; ++it) {
    const Eigen::Matrix4d W = (I + Gk * Hk).inverse();
    const Eigen::Matrix4d A1 = Ak * W * Ak;
    const Eigen::Matrix4d G1 = Gk + Ak * W * Gk * Ak.transpose();
    const Eigen::Matrix4d H1 = Hk + Ak.transpose() * Hk * W * Ak;
    const double change = (H1 - Hk).norm() / std::max(1.0, H1.norm());
    Ak = A1;
    Gk = G1;
    Hk = H1;
    if (!H1.allFinite()) break;
    if (change < 1e-14) {
      converged = true;
      break;
    }
  }
  const Eigen::Matrix4d P = Hk;
  // the residual of the Riccati equation itself, whatever the algorithm said (its terms are
  // of the order of |P| and cancel: 1e-6 relative is the rounding of R = 1e-6 against them)
  const double s = o.r + Bt.dot(P * Bt);
  const Eigen::Matrix4d residual = At.transpose() * P * At -
                                   (At.transpose() * P * Bt) * (Bt.transpose() * P * At) / s +
                                   Qt - P;
  if (!converged || !P.allFinite() || residual.norm() > 1e-5 * std::max(1.0, P.norm())) {
    *error = "preview control: the Riccati equation did not converge (dt " + std::to_string(dt) +
             ", zc " + std::to_string(o.zc) + ", r " + std::to_string(o.r) + ")";
    return false;
  }
  gi_ = Bt.dot(P * It) / s;
  gx_ = (Bt.transpose() * P * Ft) / s;
  // Gd(1) = -Gi, Gd(j) = Bt' X(j - 1) / s with X(1) = -Ac' P It, X(j) = Ac' X(j - 1)
  const Eigen::Matrix4d Ac = At - Bt * (Bt.transpose() * P * At) / s;
  gd_.assign(n, 0.0);
  gd_[0] = -gi_;
  Eigen::Vector4d X = -Ac.transpose() * P * It;
  for (int j = 1; j < n; ++j) {
    gd_[j] = Bt.dot(X) / s;
    X = Ac.transpose() * X;
  }
  return true;
}

void PreviewAxis::Reset(const PreviewGains& gains, double x0) {
  Reset(gains, Eigen::Vector3d(x0, 0, 0), x0);
}

void PreviewAxis::Reset(const PreviewGains& gains, const Eigen::Vector3d& state, double p_ref_now) {
  x_ = state;
  // at rest with p = p_ref the input must be 0 for a reference that stays: -Gi e_sum - Gx x -
  // sum Gd p_ref = 0. The preview sum of a constant reference is p_ref sum(Gd), so
  // e_sum = -(Gx x + p_ref sum Gd) / Gi; for a moving state the same formula keeps u continuous
  // against a constant reference (the caller's reference takes over from the next step).
  double sum_gd = 0;
  for (double g : gains.gd()) sum_gd += g;
  e_sum_ = -(gains.gx() * x_ + p_ref_now * sum_gd) / gains.gi();
}

void PreviewAxis::Step(const PreviewGains& gains, const double* p_ref) {
  const std::vector<double>& gd = gains.gd();
  const int n = static_cast<int>(gd.size());
  e_sum_ += gains.C() * x_ - p_ref[0];
  double preview = 0;
  for (int j = 0; j < n; ++j) preview += gd[j] * p_ref[j + 1];
  const double u = -gains.gi() * e_sum_ - gains.gx() * x_ - preview;
  x_ = gains.A() * x_ + gains.B() * u;
}

}  // namespace ohrp::walking
