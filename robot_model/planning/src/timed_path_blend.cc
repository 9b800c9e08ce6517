// Blended timing: linear segments with parabolic blends at the waypoints (planning/timed_path.h).
#include <algorithm>
#include <cmath>

#include "planning/timed_path.h"

namespace ohrp::planning {

bool TimedPath::BuildBlended(std::span<const double> v_max, std::span<const double> a_max) {
  const size_t N = points_.size() - 1;  // segments
  // each segment's duration at its slowest joint's speed limit
  std::vector<double> D(N, 0.0);
  for (size_t k = 0; k < N; ++k)
    for (int j = 0; j < n_; ++j) D[k] = std::max(D[k], std::abs(points_[k + 1][j] - points_[k][j]) / v_max[j]);
  vel_.assign(N + 2, std::vector<double>(n_, 0.0));  // vel_[k + 1]: segment k's; 0 before and after
  blend_.assign(N + 1, 0.0);
  // the blends from each velocity to the next at the acceleration the joints allow; a segment
  // whose two half blends do not fit in it is slowed (2 % a round) until they do
  for (int round = 0; round < 2000; ++round) {
    for (size_t k = 0; k < N; ++k)
      for (int j = 0; j < n_; ++j) vel_[k + 1][j] = D[k] > 0 ? (points_[k + 1][j] - points_[k][j]) / D[k] : 0.0;
    for (size_t k = 0; k <= N; ++k) {
      blend_[k] = 0;
      for (int j = 0; j < n_; ++j) blend_[k] = std::max(blend_[k], std::abs(vel_[k + 1][j] - vel_[k][j]) / a_max[j]);
    }
    bool fits = true;
    for (size_t k = 0; k < N; ++k)
      if (0.5 * (blend_[k] + blend_[k + 1]) > D[k] * (1 + 1e-12)) {
        D[k] *= 1.02;
        fits = false;
      }
    if (fits) {
      // waypoint k's time: the start blend is centred half a blend after t = 0
      times_.assign(N + 1, 0.0);
      times_[0] = 0.5 * blend_[0];
      for (size_t k = 0; k < N; ++k) times_[k + 1] = times_[k] + D[k];
      times_.push_back(times_[N] + 0.5 * blend_[N]);  // the end, at rest
      blended_ = true;
      return true;
    }
  }
  return false;  // (not reached for finite limits: the blends shrink as the segments slow)
}

double TimedPath::CornerCut(int k) const {
  if (!blended_ || k <= 0 || k + 1 >= static_cast<int>(points_.size())) return 0;
  double cut = 0;
  for (int j = 0; j < n_; ++j) cut = std::max(cut, std::abs(vel_[k + 1][j] - vel_[k][j]) * blend_[k] / 8);
  return cut;
}

void TimedPath::SampleBlended(double t, double* q, double* dq, double* ddq) const {
  const size_t N = points_.size() - 1;
  t = std::clamp(t, 0.0, times_.back());
  // in blend k (around waypoint k) or on segment k's straight part
  for (size_t k = 0; k <= N; ++k) {
    const double b = blend_[k], t0 = times_[k] - 0.5 * b;
    if (t > times_[k] + 0.5 * b && k < N) continue;
    if (t >= t0) {  // the incoming line extended, plus the parabola
      const double u = t - t0, tau = t - times_[k];
      for (int j = 0; j < n_; ++j) {
        const double a = b > 0 ? (vel_[k + 1][j] - vel_[k][j]) / b : 0.0;
        if (q) q[j] = points_[k][j] + vel_[k][j] * tau + 0.5 * a * u * u;
        if (dq) dq[j] = vel_[k][j] + a * u;
        if (ddq) ddq[j] = a;
      }
      if (k == N && t >= times_[k] + 0.5 * b) {  // at rest on the end point
        for (int j = 0; j < n_; ++j) {
          if (q) q[j] = points_[N][j];
          if (dq) dq[j] = 0;
          if (ddq) ddq[j] = 0;
        }
      }
      return;
    }
    // before blend k: on segment k-1's straight part
    const double tau = t - times_[k - 1];
    for (int j = 0; j < n_; ++j) {
      if (q) q[j] = points_[k - 1][j] + vel_[k][j] * tau;
      if (dq) dq[j] = vel_[k][j];
      if (ddq) ddq[j] = 0;
    }
    return;
  }
}

}  // namespace ohrp::planning
