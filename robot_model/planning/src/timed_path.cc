// Rest-to-rest trapezoidal timing per segment, synchronised across the joints (the blended
// timing: timed_path_blend.cc).
#include "planning/timed_path.h"

#include <algorithm>
#include <cmath>

namespace ohrp::planning {

bool TimedPath::Build(const std::vector<std::vector<double>>& waypoints,
                      std::span<const double> v_max, std::span<const double> a_max,
                      std::string* error, bool blend) {
  *this = TimedPath();
  if (waypoints.empty()) {
    *error = "a path needs at least one waypoint";
    return false;
  }
  n_ = static_cast<int>(waypoints[0].size());
  if (static_cast<int>(v_max.size()) != n_ || static_cast<int>(a_max.size()) != n_) {
    *error = "one velocity and one acceleration limit per joint of the path";
    return false;
  }
  for (int j = 0; j < n_; ++j)
    if (!(v_max[j] > 0 && a_max[j] > 0) || !std::isfinite(v_max[j]) || !std::isfinite(a_max[j])) {
      *error = "joint " + std::to_string(j) + ": velocity and acceleration limits must be > 0";
      return false;
    }
  for (const auto& w : waypoints)
    if (static_cast<int>(w.size()) != n_) {
      *error = "waypoints of different sizes";
      return false;
    }
  points_ = waypoints;
  // blended where there is an inner waypoint to pass (one segment: the same trapezoid)
  if (blend && waypoints.size() > 2 && BuildBlended(v_max, a_max)) return true;
  times_.push_back(0);
  for (size_t k = 0; k + 1 < waypoints.size(); ++k) {
    // the scalar profile s in [0, 1]: joint j moves d_j s, so its speed is |d_j| s' and its
    // acceleration |d_j| s''; the largest s' and s'' every joint allows
    double V = INFINITY, A = INFINITY;
    for (int j = 0; j < n_; ++j) {
      const double d = std::abs(waypoints[k + 1][j] - waypoints[k][j]);
      if (d == 0) continue;
      V = std::min(V, v_max[j] / d);
      A = std::min(A, a_max[j] / d);
    }
    Segment s;
    s.t0 = times_.back();
    if (std::isfinite(V)) {
      if (V * V / A >= 1) {  // a triangle: the peak speed is never reached
        s.ta = std::sqrt(1 / A);
        s.T = 2 * s.ta;
      } else {
        s.ta = V / A;
        s.T = s.ta + 1 / V;
      }
      s.a = A;
      s.v = A * s.ta;
    }
    segments_.push_back(s);
    times_.push_back(s.t0 + s.T);
  }
  return true;
}

void TimedPath::Sample(double t, double* q, double* dq, double* ddq) const {
  if (points_.empty()) return;
  if (blended_) return SampleBlended(t, q, dq, ddq);
  t = std::clamp(t, 0.0, duration());
  // the segment holding t (the last one at the end)
  size_t k = 0;
  while (k + 1 < segments_.size() && t >= times_[k + 1]) ++k;
  double s = 1, ds = 0, dds = 0;
  const std::vector<double>* p0 = &points_.back();
  const std::vector<double>* p1 = &points_.back();
  if (!segments_.empty()) {
    const Segment& g = segments_[k];
    p0 = &points_[k];
    p1 = &points_[k + 1];
    const double u = t - g.t0;
    if (g.T <= 0 || u >= g.T || t >= duration()) {
      s = 1;  // at rest on the segment's end
    } else if (u < g.ta) {
      s = 0.5 * g.a * u * u, ds = g.a * u, dds = g.a;
    } else if (u <= g.T - g.ta) {
      s = 0.5 * g.a * g.ta * g.ta + g.v * (u - g.ta), ds = g.v;
    } else {
      const double r = std::max(0.0, g.T - u);
      s = 1 - 0.5 * g.a * r * r, ds = g.a * r, dds = -g.a;
    }
  }
  for (int j = 0; j < n_; ++j) {
    const double d = (*p1)[j] - (*p0)[j];
    if (q) q[j] = (*p0)[j] + d * s;
    if (dq) dq[j] = d * ds;
    if (ddq) ddq[j] = d * dds;
  }
}

}  // namespace ohrp::planning
