// The offline pre-processing of the paper's section 4.1: which pairs of links need checking
// online. Sampling finds candidates; a pair is pruned only on a proof (collision/prune_bound.h:
// branch and bound with a certified motion bound) that it stays farther than margin + clearance
// in every posture of the box it relies on. Steps, each reported:
//  1. all pairs of links that are not parent and child;
//  2. structural pairs: touching or overlapping at the zero posture (parts built into each
//     other, as WAIST and WAIST_R of HRP-1S), or within the margin at the reference posture
//     (HRP-1S's thighs enter the waist's box at half-sitting): each gets a floor, the smaller of
//     its distances at the two postures less the margin, which the online check keeps;
//  3. samples within the joint limits (a share of joints at their limits) and local descents
//     from the closest: each pair's closest distance (a pair that came within margin + clearance
//     cannot be a never pair);
//  4. never: the others, proven clear over the box of the joint limits (the joints between the
//     pair's links);
//  5. safe ranges: for each remaining pair, a proof over the box of the ranges found so far;
//     else, joint by joint, cells of its current range proven one by one outwards from the
//     reference posture's (coarse, then sub-cells: fine), each with the other joints in their
//     current ranges (known counterexamples and cell_samples cheap samples reject a cell before
//     its proof, which gets a tenth of proof_budget); the run of proven cells, a union of proven
//     boxes, is the joint's candidate and the widest (at least min_range_share) becomes its
//     range; ranges only shrink, so every proof made stays valid;
//  6. a range covering its joint's whole range restricts nothing: its pairs do not rely on it,
//     and a pair left relying on no range is a never pair;
//  7. an independent check by samples within the final ranges (a pruned pair within margin +
//     clearance there would be a bug of the bound: it goes back online, said so in the report);
//  8. online: the pairs left (no proof within the budget is the safe side).
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "collision/pair_file.h"

namespace ohrp::collision {

struct PruneOptions {
  double margin = 0.01;      // [m] the online stop distance, written to the file
  double clearance = 0.01;   // [m] extra distance a pruned pair must keep in the samples
  int samples = 20000;       // postures sampled within the limits for step 3
  int coarse = 12;           // cells of a joint's range in the coarse scan
  int fine = 8;              // sub-cells of a boundary cell in the fine scan
  int cell_samples = 64;     // cheap samples per cell before its proof
  int verify = 2000;         // postures of the independent check of the proofs (step 7)
  int proof_budget = 20000;  // boxes one proof may measure before giving up (then not pruned)
  double descent_band = 0.05;  // [m] samples closer than keep + this start local descents
  double limit_share = 0.3;  // chance that a sampled joint sits at one of its limits
  double min_range_share = 0.25;  // a safe range must keep this share of the joint's range
  std::vector<double> reference;  // the posture safe ranges contain (by joint id); empty: zero
  std::vector<int> range_joints;  // joints that may get a safe range (segment ids); empty: all
  uint64_t seed = 1;
  // called now and then with a line of progress (may be empty)
  std::function<void(const std::string&)> progress;
};

struct PruneResult {
  SelfCollisionFile file;   // ready to write
  size_t all = 0;           // pairs in step 1
  // per pair of step 1: why it was pruned and what proved it, or why it is online; in
  // NonAdjacentPairs order
  std::vector<std::string> reasons;
  std::vector<LinkPair> pairs;  // the pairs of step 1
  std::vector<std::pair<std::string, double>> stage_seconds;  // each step's wall time [s]
};

// Runs steps 1-8 on `robot` (which must pass Validate).
PruneResult Prune(const RobotGeometry& robot, const PruneOptions& options);

// The joints whose angles move link b relative to link a (those between them in the tree).
std::vector<int> JointsBetween(const RobotGeometry& robot, int a, int b);

}  // namespace ohrp::collision
