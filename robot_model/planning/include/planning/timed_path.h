// The time parameterisation of a planned path: each straight segment between waypoints is
// traversed from rest to rest with one trapezoidal speed profile that all the group's joints
// share (synchronised: the joints arrive together, the path stays the planned polyline), its
// peak speed and acceleration the largest that keep every joint within its velocity and
// acceleration limits. Stopping at the waypoints keeps the acceleration bounded at the path's
// corners. Sample allocates nothing.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace ohrp::planning {

class TimedPath {
 public:
  // The timing of `waypoints` (group values) within `v_max` and `a_max` (per joint, > 0).
  // False with `*error` when the sizes differ or a limit is not positive and finite.
  bool Build(const std::vector<std::vector<double>>& waypoints, std::span<const double> v_max,
             std::span<const double> a_max, std::string* error);

  double duration() const { return times_.empty() ? 0 : times_.back(); }  // [s]
  int size() const { return n_; }

  // position, velocity and acceleration at time t [s] (clamped to [0, duration]); any of the
  // outputs may be null
  void Sample(double t, double* q, double* dq, double* ddq) const;

 private:
  struct Segment {
    double t0 = 0, T = 0;   // start and duration [s]
    double ta = 0;          // acceleration phase [s]
    double v = 0, a = 0;    // the profile's peak speed and acceleration [1/s, 1/s^2] of s in [0,1]
  };
  int n_ = 0;
  std::vector<std::vector<double>> points_;
  std::vector<Segment> segments_;
  std::vector<double> times_;  // each waypoint's time
};

}  // namespace ohrp::planning
