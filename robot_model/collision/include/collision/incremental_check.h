// A self-collision check that does not measure again what cannot have changed: each link's
// travel is bounded from the joint positions (a point of link l moves at most sum_j |dq_j| r_jl
// over the joints j above it: for a hinge r_jl bounds its distance from j's axis in any posture,
// from the link lengths, shape sizes and slide ranges; for a slide r_jl = 1), and a pair whose
// last measured distance (a lower bound of the gap) exceeds what its two links travelled since,
// by more than the cutoff, is still farther than the cutoff and is skipped. Every pair that can
// be within the cutoff is measured with the checker, so a Check answers exactly what
// SelfCollision::Check answers on the same pairs for every pair within the cutoff; the others
// carry a lower bound above it.
//
// Shared by the controllers' online guard (controllers/self_collision_guard.h) and sim_host's
// self_collision effect, which check a robot every control cycle. MoveTo and Check allocate,
// throw and log nothing.
#pragma once

#include <span>
#include <utility>
#include <vector>

#include "collision/geometry.h"
#include "collision/self_collision.h"

namespace ohrp::collision {

// The largest distance of a point of shape `s` from the shape's centre (p_LS) [m].
double ShapeRadius(const Shape& s);

// Per link, each joint between the base and the link with its reach: for a hinge a bound of the
// distance of any point of the link's shapes from the hinge's axis in any posture [m], for a
// slide 1 (a point moves as far as the slide): (joint id, reach). A passive joint counts as
// any other: the guard cannot command it, but it moves the links below it.
std::vector<std::vector<std::pair<int, double>>> LinkReach(const RobotGeometry& robot);

class IncrementalCheck {
 public:
  // Checks `pairs` of `checker`'s robot. The checker is borrowed (its SetPose is called by
  // Check) and must outlive this object.
  IncrementalCheck(SelfCollision* checker, std::vector<LinkPair> pairs);

  const std::vector<LinkPair>& pairs() const { return pairs_; }

  // The robot moves to `q` (one per joint id, passive joints included: NumJoints) from the last
  // posture, along any
  // path whose travel the joint differences bound. The first posture, or any angle that is not
  // finite (here or in the last posture), makes every pair's next Check measure it.
  void MoveTo(std::span<const double> q);

  // The pairs `which` (indices into pairs()) at the posture of the last MoveTo, or every pair:
  // a pair is measured (SelfCollision::Distance with `cutoff`) unless its last distance less
  // its links' travel since is above `cutoff` (by 1 um, GJK's certification tolerance).
  // `closest` is an index into pairs(). distance(i) holds each pair's value after the Check:
  // its measured distance, or when skipped a lower bound above `cutoff`.
  CheckResult Check(std::span<const int> which, double cutoff);
  CheckResult CheckAll(double cutoff);

  // Pair i was measured by the caller at the posture of the last MoveTo (SelfCollision's
  // SetPose or SetPoseOf there, then Distance): `d`, a lower bound of its gap, becomes its last
  // measurement, so later Checks bound it from d less the travel since (the guard's
  // certification measures pairs this Check only bounded; without this it would measure them
  // again every cycle).
  void Record(int i, double d);

  double distance(int i) const { return value_[i]; }
  const std::vector<double>& distances() const { return value_; }
  bool measured_now(int i) const { return measured_now_[i] != 0; }  // by the last Check
  uint64_t measured() const { return measured_; }  // pair measurements made since the start
  uint64_t skipped() const { return skipped_; }    // pair checks answered by the bound

 private:
  // one pair: measured, or answered by its bound; returns its value
  double Visit(int i, double cutoff, bool* posed);

  SelfCollision* checker_;
  std::vector<LinkPair> pairs_;
  std::vector<std::vector<std::pair<int, double>>> reach_;
  std::vector<double> q_, q_last_;   // the posture of the last MoveTo and the one before [rad]
  std::vector<double> travel_;       // per link, the sum of its motion bounds since the start [m]
  std::vector<double> travel_a_, travel_b_;  // per pair, travel_ of its links when last measured
  std::vector<double> measured_d_;   // per pair, its last measured distance [m]
  std::vector<double> value_;        // per pair, its value at the last Check [m]
  std::vector<char> measured_now_;
  uint64_t measured_ = 0, skipped_ = 0;
};

}  // namespace ohrp::collision
