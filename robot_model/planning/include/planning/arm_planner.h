// The arm planner: a collision-free path of a joint group from the posture it is in to goal
// joint values, by OMPL's bidirectional RRT (RRTConnect) in the group's configuration space (a
// box of the model's joint limits), each posture checked by PostureCheck and each straight
// motion checked every `resolution` radians of joint-space distance; then OMPL's path
// simplification (vertex reduction, shortcuts: a fixed number of rounds, each change
// re-checked; no B-spline, the timing stops at each waypoint) and
// a final check of the whole path at the same resolution, whose smallest distance is reported.
//
// Seeded: the same seed, problem and options give the same path (OMPL's random generators are
// reseeded before each plan; a plan that runs out of time may differ). Not thread-safe: one plan
// at a time per process (OMPL's seed is global).
#pragma once

#include <span>
#include <string>
#include <vector>

#include "planning/posture_check.h"

namespace ohrp::planning {

struct PlanOptions {
  double time_limit = 2.0;    // [s] for RRTConnect
  double resolution = 0.01;   // [rad] largest joint-space step between checked postures
  double range = 0;           // [rad] RRTConnect's step; 0: OMPL's default (a fifth of the extent)
  unsigned seed = 1;          // OMPL's random seed (> 0)
  bool simplify = true;
};

// what a plan found
struct PlanResult {
  bool solved = false;
  std::string reason;         // why not: the start or goal refused (which pair, which joint),
                              // or no path found in the time
  std::vector<std::vector<double>> waypoints;  // group values, start first, goal last
  double plan_time = 0;       // [s] RRTConnect
  double simplify_time = 0;   // [s]
  double raw_length = 0;      // [rad] joint-space (Euclidean) length before simplification
  double length = 0;          // [rad] after
  Verdict closest;            // the closest pair along the final path (checked at resolution)
  long evaluations = 0;       // posture checks the plan made
};

// Plans the group of `check` from `posture` (a whole posture: the group's start and the other
// joints, which stay) to `goal` (group values). Refuses, with the reason, a start or goal outside
// the limits or closer than check.required() to something.
PlanResult PlanJoints(PostureCheck& check, std::span<const double> posture,
                      std::span<const double> goal, const PlanOptions& options);

// the joint-space length of a polyline of group values [rad]
double PathLength(const std::vector<std::vector<double>>& waypoints);

// The closest pair along the straight segments of `waypoints` (group values) set into
// `posture`, each segment checked every `resolution` [rad].
Verdict ClosestAlong(PostureCheck& check, std::span<const double> posture,
                     const std::vector<std::vector<double>>& waypoints, double resolution);

}  // namespace ohrp::planning
