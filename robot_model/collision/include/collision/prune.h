// The offline pre-processing of the paper's section 4.1: which pairs of links need checking
// online. Steps, each reported:
//  1. all pairs of links that are not parent and child;
//  2. structural pairs: touching or overlapping at the zero posture (parts built into each
//     other, as WAIST and WAIST_R of HRP-1S), or within the margin at the reference posture
//     (HRP-1S's thighs enter the waist's box at half-sitting): skipped, the online check would
//     hold the robot where it stands;
//  3. never: pairs that stay farther than margin + clearance in every sampled posture within
//     the joint limits (uniform samples, a share of joints at their limits) and in local
//     descents of their distance from the closest samples;
//  4. safe ranges: for each remaining pair, each joint between its two links is scanned at a
//     coarse resolution (cells of its range, sampled postures in each cell and descents from
//     the closest); the run of safe
//     cells around the reference posture, widened at a fine resolution into the neighbouring cells,
//     is the joint's safe range for that pair; the widest (at least `min_range_share` of the
//     joint's range) wins and the pair is pruned while the joint keeps to it. A joint's ranges
//     only shrink, so earlier pairs stay safe;
//  5. verification: postures sampled with each safe range kept or left at random; a pruned
//     pair that no left range covers and that comes within margin + clearance (in a sample or
//     a descent from a near one) goes back online;
//  6. online: the pairs left.
// It is sampling: the brute-force test checks it against MuJoCo on postures it did not see.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "collision/pair_file.h"

namespace ohrp::collision {

struct PruneOptions {
  double margin = 0.01;      // [m] the online stop distance, written to the file
  double clearance = 0.01;   // [m] extra distance a pruned pair must keep in the samples
  int samples = 20000;       // postures sampled within the limits for step 3
  int coarse = 12;           // cells of a joint's range in the coarse scan
  int fine = 8;              // sub-cells of a boundary cell in the fine scan
  int cell_samples = 64;     // postures per cell
  int verify = 100000;       // postures of the final verification (step 5)
  int max_descents = 64;     // descents per pair in the verification
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
  // per pair of step 1: why it was pruned, or "online"; in NonAdjacentPairs order
  std::vector<std::string> reasons;
  std::vector<LinkPair> pairs;  // the pairs of step 1
};

// Runs steps 1-5 on `robot` (which must pass Validate).
PruneResult Prune(const RobotGeometry& robot, const PruneOptions& options);

// The joints whose angles move link b relative to link a (those between them in the tree).
std::vector<int> JointsBetween(const RobotGeometry& robot, int a, int b);

}  // namespace ohrp::collision
