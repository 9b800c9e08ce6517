// The actuator's -3 dB bandwidth from a chirp (see identify/sensors.h).
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "identify/sensors.h"

namespace ohrp::identify {
namespace {

// a sin(phase) + b cos(phase) + c + d t over [i0, i1): the amplitude and its standard error
Stat Amplitude(const std::vector<double>& t, const std::vector<double>& y,
               const std::vector<double>& phase, size_t i0, size_t i1) {
  const long n = static_cast<long>(i1 - i0);
  Eigen::MatrixXd a(n, 4);
  Eigen::VectorXd v(n);
  const double tm = 0.5 * (t[i0] + t[i1 - 1]);
  for (long k = 0; k < n; ++k) {
    const double s = t[i0 + k] - tm;
    a.row(k) << std::sin(phase[i0 + k]), std::cos(phase[i0 + k]), 1.0, s;
    v(k) = y[i0 + k];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(v);
  const double s2 = (v - a * x).squaredNorm() / std::max<long>(1, n - 4);
  const Eigen::MatrixXd cov = s2 * (a.transpose() * a).inverse();
  Stat e;
  e.value = std::hypot(x(0), x(1));
  if (e.value > 0) {  // delta method through the hypotenuse
    const double ga = x(0) / e.value, gb = x(1) / e.value;
    e.se = std::sqrt(std::max(0.0, ga * ga * cov(0, 0) + gb * gb * cov(1, 1) + 2 * ga * gb * cov(0, 1)));
  }
  return e;
}

// the reference's crossings of its mean, upward (`up`) and both ways (`all`), and its phase:
// 0 at an upward crossing, pi at a downward one, linear in time between them (a chirp's is
// quadratic: over half a period the difference is small)
struct Crossings {
  std::vector<size_t> up, all;
  std::vector<double> phase;
};

Crossings Cross(const std::vector<double>& t, const std::vector<double>& ref) {
  double mean = 0;
  for (double r : ref) mean += r;
  mean /= static_cast<double>(ref.size());
  Crossings c;
  std::vector<double> at;  // the crossing's time, interpolated
  for (size_t k = 1; k < ref.size(); ++k) {
    const bool up = ref[k - 1] < mean && ref[k] >= mean, down = ref[k - 1] >= mean && ref[k] < mean;
    if (!up && !down) continue;
    if (c.all.empty() && !up) continue;  // the phase counts from an upward crossing
    if (up) c.up.push_back(k);
    c.all.push_back(k);
    const double f = (mean - ref[k - 1]) / (ref[k] - ref[k - 1]);
    at.push_back(t[k - 1] + f * (t[k] - t[k - 1]));
  }
  c.phase.assign(ref.size(), 0.0);
  for (size_t i = 0; i + 1 < c.all.size(); ++i)
    for (size_t k = c.all[i]; k < c.all[i + 1]; ++k)
      c.phase[k] = M_PI * (static_cast<double>(i) + (t[k] - at[i]) / (at[i + 1] - at[i]));
  return c;
}

}  // namespace

bool EstimateBandwidth(const JointLog& l, Bandwidth* b, std::string* error) {
  *b = Bandwidth{};
  const Crossings c = Cross(l.t, l.ref);
  const std::vector<size_t>& up = c.up;
  if (up.size() < 8) {
    *error = l.joint + ": the reference crosses its mean upwards " + std::to_string(up.size()) +
             " times (need 8 for the magnitude over frequency): not a chirp";
    return false;
  }
  for (size_t i = 0; i + 2 < up.size(); ++i) {
    const size_t i0 = up[i], i1 = up[i + 2];
    if (i1 - i0 < 16) break;  // fewer than 8 samples a period: the sampling's limit
    const double f = 2.0 / (l.t[i1] - l.t[i0]);
    const Stat r = Amplitude(l.t, l.ref, c.phase, i0, i1);
    const Stat q = Amplitude(l.t, l.q, c.phase, i0, i1);
    if (!(r.value > 0)) continue;
    b->freq.push_back(f);
    b->mag.push_back(q.value / r.value);
    b->mag_se.push_back(std::hypot(q.se / r.value, q.value * r.se / (r.value * r.value)));
  }
  const size_t n = b->freq.size();
  if (n < 6) {
    *error = l.joint + ": " + std::to_string(n) + " windows of the chirp (need 6)";
    return false;
  }
  b->f_max = *std::max_element(b->freq.begin(), b->freq.end());
  b->gain0 = (b->mag[0] + b->mag[1] + b->mag[2]) / 3.0;
  // -3 dB of the tracking: |q / ref| = 1 / sqrt(2) (0 dB a servo that follows its reference)
  const double level = 1 / std::sqrt(2.0);
  if (b->mag[0] < level) {
    *error = l.joint + ": the magnitude is below -3 dB already at the chirp's lowest frequency (" +
             std::to_string(b->freq[0]) + " Hz): a slower start";
    return false;
  }
  size_t cross = 0;
  for (size_t i = 1; i < n && cross == 0; ++i)
    if (b->mag[i] < level && b->mag[i - 1] >= level) cross = i;
  if (cross == 0) return true;  // above -3 dB throughout: the bandwidth is above f_max
  // a straight line through the windows within 15 % of the crossing's frequency (at least 2 each
  // side), weighted by the magnitudes' standard errors
  const double fc0 = b->freq[cross];
  std::vector<size_t> near;
  for (size_t i = 0; i < n; ++i)
    if (std::fabs(b->freq[i] - fc0) <= 0.15 * fc0 || (i + 2 >= cross && i <= cross + 1)) near.push_back(i);
  Eigen::MatrixXd a(near.size(), 2);
  Eigen::VectorXd y(near.size());
  for (size_t k = 0; k < near.size(); ++k) {
    a.row(k) << 1.0, b->freq[near[k]];
    y(k) = b->mag[near[k]];
  }
  const Eigen::VectorXd x = a.colPivHouseholderQr().solve(y);
  const double s2 = (y - a * x).squaredNorm() / std::max<long>(1, a.rows() - 2);
  // the residual's scatter, or the magnitudes' own standard errors if larger
  double se2 = 0;
  for (size_t i : near) se2 += b->mag_se[i] * b->mag_se[i];
  se2 /= static_cast<double>(near.size());
  const Eigen::Matrix2d cov = std::max(s2, se2) * (a.transpose() * a).inverse();
  if (!(x(1) < 0)) {
    *error = l.joint + ": the magnitude does not fall through -3 dB near " + std::to_string(fc0) + " Hz";
    return false;
  }
  b->found = true;
  b->f = (level - x(0)) / x(1);
  // d f / d a0 = -1 / a1, d f / d a1 = -f / a1
  const double var = (cov(0, 0) + b->f * b->f * cov(1, 1) + 2 * b->f * cov(0, 1)) / (x(1) * x(1));
  // and the chirp's: a window's magnitude is that of the frequencies it spans (about two windows'
  // steps), taken as uniform over that span
  const double span = std::fabs(b->freq[cross] - b->freq[cross >= 2 ? cross - 2 : 0]);
  b->f_fit_se = std::sqrt(std::max(0.0, var));
  b->f_se = std::hypot(b->f_fit_se, span / std::sqrt(12.0));
  return true;
}

}  // namespace ohrp::identify
