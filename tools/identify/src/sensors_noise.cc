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

#include <cstdio>

#include "identify/sensors.h"
#include "sensors_table.h"

namespace ohrp::identify {
namespace {

// v less its centred moving average of `width` samples, at rows [h, n - h)
std::vector<double> HighPass(const std::vector<double>& v, int width) {
  std::vector<double> out = detail::MovingAverage(v, width);
  const size_t h = static_cast<size_t>(width / 2);
  for (size_t i = 0; i < out.size(); ++i) out[i] = v[h + i] - out[i];
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

namespace {

// the row times' central difference of x (one-sided at the ends): the encoder's velocity
std::vector<double> Derivative(const std::vector<double>& t, const std::vector<double>& x) {
  std::vector<double> d(x.size(), 0.0);
  for (size_t k = 0; k < x.size() && x.size() > 1; ++k) {
    const size_t a = k == 0 ? 0 : k - 1, b = k + 1 == x.size() ? k : k + 1;
    d[k] = (x[b] - x[a]) / (t[b] - t[a]);
  }
  return d;
}

// a warning when the motion took more than max_explained of the channel's high-passed variance
// and the noise left is above `floor` (below it the channel is noise-free: a simulation without
// noise, whose tiny remainder the motion explains whole)
void Explained(const std::string& what, double share, double noise, double floor,
               const SensorOptions& o, std::vector<std::string>* warnings) {
  if (!(share > o.max_explained) || !(noise > floor)) return;
  char buf[320];
  std::snprintf(buf, sizeof(buf), "the robot's own motion explains %.0f %% of %s's high-passed "
                "variance: its noise is the remainder, trust it less (a stiller window?)",
                100 * share, what.c_str());
  warnings->push_back(buf);
}

}  // namespace

namespace detail {

void MotionNoise(Table& t, const std::string& j, const SensorOptions& o, SensorEstimates* out) {
  const std::vector<double>& q = t.col["q_" + j];
  const std::vector<double> dq_enc = Derivative(t.col["time"], q);
  double share = 0;
  const bool has_dq = t.Has("dq_" + j);
  if (has_dq) {
    out->velocity_noise.push_back(NoiseBeyondMotion(t.col["dq_" + j], {dq_enc}, o.width, &share));
    out->velocity_explained.push_back(share);
    Explained("dq_" + j, share, out->velocity_noise.back().value, 1e-6, o, &out->warnings);
  }
  if (!t.Has("tau_" + j)) {
    out->torque_noise.push_back({NAN, NAN}), out->torque_explained.push_back(NAN);
    return;
  }
  // the angle, the encoder's velocity and the logged one: each regressor's own noise only
  // attenuates what it explains; the least noisy carries the motion
  std::vector<std::vector<double>> motion{q, dq_enc};
  if (has_dq) motion.push_back(t.col["dq_" + j]);
  out->torque_noise.push_back(NoiseBeyondMotion(t.col["tau_" + j], motion, o.width, &share));
  out->torque_explained.push_back(share);
  Explained("tau_" + j, share, out->torque_noise.back().value, 1e-4, o, &out->warnings);
}

bool OrientationNoise(Table& t, const SensorOptions& o, ImuEstimate* u,
                      std::vector<std::string>* warnings, std::string* error) {
  const std::string qn = u->name + "_q";
  std::vector<double> e[3];
  OrientationErrors(t.col[qn + "w"], t.col[qn + "x"], t.col[qn + "y"], t.col[qn + "z"], e);
  const std::vector<double>& time = t.col["time"];
  std::vector<std::vector<double>> turn(3, std::vector<double>(time.size(), 0.0));
  const char* axis = "xyz";
  for (int k = 0; k < 3; ++k) {
    const std::vector<double>& g = t.col[u->name + "_g" + axis[k]];
    for (size_t r = 1; r < time.size(); ++r)  // the gyro's integral (trapezoids), small angles
      turn[k][r] = turn[k][r - 1] + 0.5 * (g[r] + g[r - 1]) * (time[r] - time[r - 1]);
  }
  double var = 0, dof = 0;
  for (int k = 0; k < 3; ++k) {
    Stat& s = u->orientation_noise[k];
    s = NoiseBeyondMotion(e[k], turn, o.width, &u->orientation_explained[k]);
    if (!Still(u->name + " orientation about " + axis[k], e[k], s, o.width, o.orientation_still, error))
      return false;
    Explained(u->name + "'s orientation about " + std::string(1, axis[k]),
              u->orientation_explained[k], s.value, 1e-7, o, warnings);
    const double n = s.se > 0 ? 0.5 * std::pow(s.value / s.se, 2) : 0;
    var += n * s.value * s.value, dof += n;
  }
  if (dof > 0) u->orientation_noise_pooled = {std::sqrt(var / dof), std::sqrt(var / dof / (2 * dof))};
  return true;
}

}  // namespace detail
}  // namespace ohrp::identify
