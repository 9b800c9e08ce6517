// A damped sine fitted to a window of samples by least squares, for oscillations damped too
// heavily for the extrema method of oscillation.h (fewer than four swings above the noise: soles
// with a damping ratio of 0.2 to 0.5):
//   x(t) = c + exp(-sigma u) (a cos(omega u) + b sin(omega u)),  u = t - t[begin]
// Levenberg-Marquardt on the five parameters from a start (sigma0, omega0: GridStart's, or the
// caller's), the linear ones (c, a, b) solved exactly at the start. Standard errors from the covariance s^2 (J^T J)^-1,
// s^2 the residual variance.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace ohrp::compare {

struct DampedFit {
  bool ok = false;
  std::string why;                       // when not ok
  double c = 0, a = 0, b = 0;            // offset and the two amplitudes at t[begin]
  double sigma = 0, omega = 0;           // [1/s], [rad/s]
  double sigma_se = 0, omega_se = 0, cov_sigma_omega = 0;
  double rms = 0;                        // of the residuals
  double explained = 0;                  // 1 - RSS / (the samples' variance x n)
  int iterations = 0;
};

// A start for the fit: the (sigma, omega) of a grid (periods from the window's length down to 8
// samples, damping ratios 0 to 0.7) whose best linear part leaves the least residual.
bool GridStart(const std::vector<double>& t, const std::vector<double>& x, size_t begin, size_t end,
               double* sigma0, double* omega0);

DampedFit FitDampedSine(const std::vector<double>& t, const std::vector<double>& x, size_t begin,
                        size_t end, double sigma0, double omega0);

}  // namespace ohrp::compare
