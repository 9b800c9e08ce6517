// The proof behind every pruned pair (collision/prune.h): a pair of links is clear of a distance
// `keep` over a box of postures (each joint between its two links within [lo, hi]) when, at the
// box's centre, the checker's lower bound of the pair's distance exceeds keep plus the most the
// two links can move relative to each other over the box; otherwise the box is split in two along
// its widest weighted joint (branch and bound) until every sub-box is proven, a centre within
// keep is found (a counterexample: the pair is not clear over the box), or the budget of boxes
// runs out (not proven: the safe side).
//
// The motion bound: along the straight path from the centre c to any posture q of the box a point
// of link l moves, relative to the two links' common ancestor, at most sum_j |q_j - c_j| rho_jl
// over the joints j between the links, rho_jl the largest distance of a point of l from j's axis
// anywhere in the box (1 for a slide). rho_jl is bounded by the smaller of LinkReach's
// posture-independent reach and, at the centre, the distance of l's bounding sphere from j's axis
// plus its radius plus the sphere centre's own drift over the box from the joints between j and l
// (their half-widths times their rho, from the link upwards). So for every q in the box, distance(q) >=
// distance(c) - sum_j h_j rho_jl, h_j the half-widths: a bound, not a sample.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "collision/geometry.h"
#include "collision/self_collision.h"

namespace ohrp::collision {

struct ProofResult {
  bool proven = false;        // every posture of the box keeps the pair farther than keep
  bool counterexample = false;  // a posture of the box within keep was found (`witness`)
  double certified = 0;       // proven: a lower bound of the pair's distance over the box [m]
  int boxes = 0;              // boxes measured
  std::vector<double> witness;  // the posture within keep (by joint id), when counterexample
};

class PairProver {
 public:
  // `checker` is borrowed (its SetPose is called) and must outlive this object.
  explicit PairProver(SelfCollision* checker);

  // Proves link pair p farther than `keep` over the box lo..hi (full vectors by joint id; only
  // the joints between the pair's links matter, JointsBetween), measuring at most `budget`
  // boxes.
  ProofResult Prove(LinkPair p, const std::vector<double>& lo, const std::vector<double>& hi,
                    double keep, int budget);

  // The motion bound of the pair over the box of half-widths `half` (by joint id) about the
  // posture of the checker's last SetPose (the centre), and each joint's share of it
  // (`weight`, by joint index in `joints`): sum_j half_j rho_jl.
  double MotionBound(LinkPair p, const std::vector<int>& joints, const std::vector<double>& half,
                     std::vector<double>* weight) const;

 private:
  SelfCollision* c_;
  std::vector<std::vector<std::pair<int, double>>> reach_;  // LinkReach
  std::vector<int> link_of_joint_;      // the link each joint moves
  std::vector<Eigen::Vector3d> centre_L_;  // each link's bounding sphere in its frame
  std::vector<double> radius_;
};

}  // namespace ohrp::collision
