// Synthetic signals with closed forms for the comparison tests: a damped oscillation that
// starts at a known time (flat before, as a push's release), seeded Gaussian noise.
#pragma once

#include <cmath>
#include <random>

namespace ohrp::compare::testing {

// x(t) = c for t < t0, c + amp exp(-sigma (t - t0)) sin(omega_d (t - t0)) after, with
// omega_d = 2 pi f_d and sigma = zeta omega_n, omega_n = omega_d / sqrt(1 - zeta^2)
struct Damped {
  double f_d = 1.7, zeta = 0.05, amp = 1.0, t0 = 2.0, c = 0.0;
  double omega_d() const { return 2 * M_PI * f_d; }
  double sigma() const { return zeta * omega_d() / std::sqrt(1 - zeta * zeta); }
  double log_decrement() const { return sigma() / f_d; }  // sigma T_d
  double operator()(double t) const {
    if (t < t0) return c;
    return c + amp * std::exp(-sigma() * (t - t0)) * std::sin(omega_d() * (t - t0));
  }
};

struct Noise {
  explicit Noise(double sd, unsigned seed) : rng(seed), dist(0.0, sd) {}
  double operator()() { return sd_zero() ? 0.0 : dist(rng); }
  bool sd_zero() const { return dist.stddev() == 0; }
  std::mt19937 rng;
  std::normal_distribution<double> dist;
};

}  // namespace ohrp::compare::testing
