// ohrp identify --sensors: the noise of the channels a still robot's own motion also moves (the
// joints' velocity and torque, the IMU's orientation; see identify/sensors.h, NoiseBeyondMotion).
//
// Why the motion's part is removed and how. The centred moving average (NoiseStd) takes out what
// is slower than its width (51 samples: about 4 Hz at 5 ms), but a standing robot's servos and
// soles also move it faster than that: a torque follows the joint's high-passed angle and
// velocity through the servo's gains, an orientation follows the body's sway, which the gyro
// measures. Those parts are fitted away by least squares on the high-passed signals that measure
// the motion (regressors), and the noise is the std of what remains, with the degrees of freedom
// the fit took counted. Regressors measured with noise of their own (an encoder) only explain less
// of the motion (their coefficient is attenuated); they do not bias the remainder, since their
// noise is independent of the channel's (a fit on p independent regressors takes p of the n
// degrees of freedom, which the (n - p - 1) divides out).
#include <Eigen/Dense>
#include <cmath>

#include "identify/sensors.h"

namespace ohrp::identify {
namespace {

// v less its centred moving average of `width` samples, at rows [h, n - h)
std::vector<double> HighPass(const std::vector<double>& v, int width) {
  const size_t h = static_cast<size_t>(width / 2), n = v.size();
  std::vector<double> out;
  if (n < 2 * h + 1) return out;
  double sum = 0;
  for (size_t k = 0; k < 2 * h + 1; ++k) sum += v[k];
  for (size_t k = h; k + h < n; ++k) {
    out.push_back(v[k] - sum / (2 * h + 1));
    if (k + h + 1 < n) sum += v[k + h + 1] - v[k - h];
  }
  return out;
}

}  // namespace

Stat NoiseBeyondMotion(const std::vector<double>& x, const std::vector<std::vector<double>>& motion,
                       int width, double* explained) {
  Stat e;
  if (explained) *explained = 0;
  const std::vector<double> y = HighPass(x, width);
  const size_t m = y.size(), p = motion.size();
  if (m < p + 3) return e;
  Eigen::MatrixXd A(m, p + 1);
  Eigen::VectorXd b(m);
  for (size_t i = 0; i < m; ++i) b(i) = y[i], A(i, p) = 1.0;
  for (size_t k = 0; k < p; ++k) {
    const std::vector<double> r = HighPass(motion[k], width);
    if (r.size() != m) return e;
    for (size_t i = 0; i < m; ++i) A(i, k) = r[i];
  }
  // regressors scaled to unit norm (a torque against an angle of 1e-5 rad), a pivoted QR: a
  // regressor that does not move (a held joint's zero velocity) drops out instead of failing
  for (size_t k = 0; k <= p; ++k) {
    const double norm = A.col(k).norm();
    if (norm > 0) A.col(k) /= norm;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);
  const Eigen::VectorXd r = b - A * qr.solve(b);
  const double rss = r.squaredNorm(), tss = (b.array() - b.mean()).matrix().squaredNorm();
  const double dof = static_cast<double>(m) - static_cast<double>(qr.rank());
  e.value = std::sqrt(rss / dof / (1.0 - 1.0 / width));
  e.se = e.value / std::sqrt(2 * dof);
  if (explained) *explained = tss > 0 ? 1.0 - rss / tss : 0.0;
  return e;
}

void OrientationErrors(const std::vector<double>& w, const std::vector<double>& x,
                       const std::vector<double>& y, const std::vector<double>& z,
                       std::vector<double> out[3]) {
  for (int k = 0; k < 3; ++k) out[k].clear();
  if (w.empty()) return;
  const Eigen::Quaterniond q0(w[0], x[0], y[0], z[0]);
  for (size_t i = 0; i < w.size(); ++i) {
    // the rotation from the first sample's frame to this one's, in the first's (the IMU's) frame:
    // the sensor model turns the orientation by its error on the right (q d)
    Eigen::Quaterniond d = q0.conjugate() * Eigen::Quaterniond(w[i], x[i], y[i], z[i]);
    if (d.w() < 0) d.coeffs() *= -1;
    const double s = d.vec().norm();
    const double angle = 2 * std::atan2(s, d.w());
    const Eigen::Vector3d v = s > 0 ? Eigen::Vector3d(d.vec() * (angle / s)) : Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) out[k].push_back(v(k));
  }
}

}  // namespace ohrp::identify
