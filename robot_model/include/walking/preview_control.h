// Preview control of the cart-table model (Kajita et al. 2003, "Biped walking pattern
// generation by using preview control of zero-moment point"): the CoM of a linear inverted
// pendulum at constant height zc, driven by its jerk so that its ZMP p = x - (zc / g) ddx
// follows a reference known `preview_time` ahead.
//
// One horizontal axis, sampled at dt: state x = (x, dx, ddx), input u = jerk,
//   x(k+1) = A x(k) + B u(k),   p(k) = C x(k)
//   A = [1 dt dt^2/2; 0 1 dt; 0 0 1], B = [dt^3/6; dt^2/2; dt], C = [1 0 -zc/g].
// The servo of Katayama et al. (1985), as in Kajita 2003: the error e = p - p_ref is integrated
// and the cost sum(Q e^2 + R du^2) over the augmented system (e, dx) is minimised; the gains come
// from the discrete algebraic Riccati equation, solved once at construction:
//   u(k) = -Gi sum_{i<=k} e(i) - Gx x(k) - sum_{j=1..N} Gd(j) p_ref(k + j)
// with N = round(preview_time / dt). Both horizontal axes share the gains (PreviewAxis each).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ohrp::walking {

struct PreviewOptions {
  double dt = 0.005;           // [s] the control period
  double zc = 0.8;             // [m] CoM height above the ZMP plane
  double gravity = 9.81;       // [m/s^2]
  double preview_time = 1.6;   // [s]
  double q = 1.0;              // weight of the ZMP error
  double r = 1e-6;             // weight of the input change
};

class PreviewGains {
 public:
  // Solves the Riccati equation; false with `*error` when the options are not usable
  // (non-positive dt, zc, gravity, preview time or weights, or no convergence).
  bool Compute(const PreviewOptions& options, std::string* error);

  const PreviewOptions& options() const { return options_; }
  int horizon() const { return static_cast<int>(gd_.size()); }  // N
  double gi() const { return gi_; }
  const Eigen::RowVector3d& gx() const { return gx_; }
  const std::vector<double>& gd() const { return gd_; }  // Gd(1..N) at [0..N-1]
  const Eigen::Matrix3d& A() const { return A_; }
  const Eigen::Vector3d& B() const { return B_; }
  const Eigen::RowVector3d& C() const { return C_; }

 private:
  PreviewOptions options_;
  Eigen::Matrix3d A_;
  Eigen::Vector3d B_;
  Eigen::RowVector3d C_;
  double gi_ = 0;
  Eigen::RowVector3d gx_;
  std::vector<double> gd_;
};

// One axis of the preview servo. No allocation, no throw.
class PreviewAxis {
 public:
  // starts at rest at `x0` with the error integral chosen so that the servo holds it there
  // when the reference stays at `x0`
  void Reset(const PreviewGains& gains, double x0);
  // the same with a moving state (x, dx, ddx): a re-start keeps the CoM continuous
  void Reset(const PreviewGains& gains, const Eigen::Vector3d& state, double p_ref_now);
  // one step: `p_ref` holds N + 1 samples, p_ref[0] the reference now (time k), p_ref[j] at k + j
  void Step(const PreviewGains& gains, const double* p_ref);
  // the state moved by `dx` (x, dx, ddx), the error integral kept: the servo's feedback takes the
  // new state on towards the reference from the next step (a plan re-based on a measured state)
  void Shift(const Eigen::Vector3d& dx) { x_ += dx; }

  const Eigen::Vector3d& state() const { return x_; }  // x, dx, ddx after the last step
  double zmp(const PreviewGains& gains) const { return gains.C() * x_; }  // of the state

 private:
  Eigen::Vector3d x_ = Eigen::Vector3d::Zero();
  double e_sum_ = 0;
};

}  // namespace ohrp::walking
