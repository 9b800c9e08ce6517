// Walking figures derived from the robot where neither the command line nor the robot profile
// (nor a --params file) sets them (docs/robots.md, "Derived from the robot").
//
// Stride, swing height and step time by dynamic similarity (Alexander's Froude scaling): two
// legged walkers move alike when their lengths are the same multiples of the leg length L and
// their times the same multiples of sqrt(L / g). Anchored on HRP-1S, the robot walk's defaults
// were tuned on (walking::StepLimits::max_forward 0.25 m, GaitOptions::step_height 0.04 m and
// step_time 0.8 s): for a leg of length L, with r = L / L_HRP-1S,
//   max_forward = 0.25 r,  step_height = 0.04 r,  step_time = 0.8 sqrt(r)
// (g the same on both). A leg within kSameLeg of HRP-1S's gets the defaults exactly, so
// HRP-1S's figures do not change.
#pragma once

#include <cmath>
#include <string>

namespace ohrp::controllers {

// HRP-1S's leg (mjcf/hrp1s/hrp1s.xml: the hip joint to the sole's centre along the left leg's
// anchors, WalkController::LegLength at its stance) [m]
constexpr double kAnchorLegLength = 0.7425;
// a leg within this share of the anchor's is the anchor's (its figures unchanged)
constexpr double kSameLeg = 0.001;

struct DerivedGait {
  double ratio = 1;         // L / L_anchor (1 when within kSameLeg)
  double max_forward = 0;   // [m]
  double step_height = 0;   // [m]
  double step_time = 0;     // [s]
};

// The anchor's figures (stride [m], swing apex [m], step time [s]) scaled to a leg of `leg` m
// against an anchor leg of `anchor_leg` m; `leg` > 0, `anchor_leg` > 0.
DerivedGait ScaleGait(double leg, double anchor_leg, double stride, double step_height,
                      double step_time);

// The load feed-forward's rule: on when the stance leg, carrying the whole weight at the stance
// pose (single support at lift-off, the CoM still between the feet), would sag by more than
// kSagLimit at one of its joints: max_j |tau_j| / kp_j, tau the single-support torques
// (LoadFeedforward::Compute with shares 1, 0), kp the servo's stiffness as balance and walk
// command it (the suggested kp times (servo_frequency / 6)^2).
constexpr double kSagLimit = 0.01;  // [rad]

struct SagEstimate {
  double sag = 0;       // [rad] the largest |tau| / kp over the stance leg's joints
  int joint = -1;       // where (index in the robot's joints), -1: no joint with kp > 0
  double tau = 0;       // [N m] its torque
  double kp = 0;        // [N m/rad] its stiffness
};

// The largest sag over joints `leg` given their torques and stiffnesses (indexed by joint).
SagEstimate LargestSag(const int* leg, int n, const double* tau, const double* kp);

// The stabilizer's foot rotation damping control (stabilizer.h) turns a sole by
//   d theta / dt = (n_measured - n_desired) / D
// and the ankle's torque answers a turn theta with its servo's stiffness K: the measured
// torque follows the desired one with the time constant D / K. HRP-1S's D (300 N m s/rad)
// against its ankles' 17000 N m/rad gives 0.018 s (its torque then limited by the soles'
// contact); a robot with soft ankle servos would follow in D / K (0.57 s on the tall robot's
// 524 N m/rad ankles: longer than a step's single support, while the DCM diverges with the
// pendulum's time constant sqrt(z / g), 0.29 s). D is kept at most K kAnkleTorqueShare
// sqrt(z / g), z the stance CoM height over the soles.
constexpr double kAnkleTorqueShare = 0.7;  // [-] of the pendulum's time constant
// a joint is an ankle joint of an axis when |cos| between its axis and the base's is above this
constexpr double kAnkleAxisAlignment = 0.95;

struct AnkleStiffness {
  double kp = INFINITY;  // [N m/rad] the least over the ankles' roll and pitch joints
  int joint = -1;        // where (index in the robot's joints), -1: none
};

// D for ankles of stiffness `kp`: min(default_d, kp time_constant); default_d when kp is not > 0
double AnkleDamping(double kp, double default_d, double time_constant);

// The stride of a leg whose servos yield: a stance leg that would sag by `sag` [rad] under the
// whole weight (LargestSag, before the feed-forward) lets the hip move up to leg x sag [m]; the
// stride keeps that much less than the stiff leg's `stride` (at least half of it). Unchanged when
// the sag is within kSagLimit (a leg that needs no feed-forward).
double CompliantStride(double stride, double leg, double sag);

}  // namespace ohrp::controllers
