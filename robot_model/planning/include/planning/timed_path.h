// The time parameterisation of a planned path, within each joint's velocity and acceleration
// limits. Two ways:
//   rest to rest  each straight segment between waypoints is traversed with one trapezoidal
//                 speed profile that all the group's joints share (synchronised: the joints
//                 arrive together, the path stays the planned polyline), stopping at every
//                 waypoint: the acceleration stays bounded at the path's corners;
//   blended       (linear segments with parabolic blends, smoothing the corners): each segment
//                 at one constant velocity (its slowest joint at its limit), and at each inner
//                 waypoint a parabolic blend, centred on the waypoint's time, from one
//                 segment's velocity to the next at the acceleration the joints allow; the
//                 motion starts and ends at rest on the end points but does not stop at the
//                 inner ones: it passes within |V_k - V_k-1| b_k / 8 of each (b_k: the blend's
//                 duration), so the corners are cut and the blended path must be checked again
//                 (reach does, and falls back to rest to rest where it is not clear). Segments
//                 too short for their blends are slowed until the blends fit.
// Sample allocates nothing.
#pragma once

#include <span>
#include <string>
#include <vector>

namespace ohrp::planning {

class TimedPath {
 public:
  // The timing of `waypoints` (group values) within `v_max` and `a_max` (per joint, > 0).
  // False with `*error` when the sizes differ or a limit is not positive and finite.
  // `blend`: blended at the inner waypoints (above), else rest to rest.
  bool Build(const std::vector<std::vector<double>>& waypoints, std::span<const double> v_max,
             std::span<const double> a_max, std::string* error, bool blend = false);
  bool blended() const { return blended_; }
  // blended: how far the path may pass from inner waypoint k (1 .. n-2) [rad or m, per joint
  // the largest]: |V_k - V_k-1| b_k / 8; 0 for the end points and rest to rest
  double CornerCut(int k) const;
  // waypoint k's time [s]: when it is reached (rest to rest; blended: the first at 0, the last
  // at the end), or when an inner waypoint's blend is half done (blended)
  double WaypointTime(int k) const {
    if (!blended_ || (k > 0 && k + 1 < static_cast<int>(points_.size()))) return times_[k];
    return k == 0 ? 0.0 : times_.back();
  }

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
  bool BuildBlended(std::span<const double> v_max, std::span<const double> a_max);
  void SampleBlended(double t, double* q, double* dq, double* ddq) const;
  int n_ = 0;
  std::vector<std::vector<double>> points_;
  std::vector<Segment> segments_;
  std::vector<double> times_;  // each waypoint's time
  // blended: per segment its velocity (per joint), per waypoint its blend's duration [s]
  bool blended_ = false;
  std::vector<std::vector<double>> vel_;
  std::vector<double> blend_;
};

}  // namespace ohrp::planning
