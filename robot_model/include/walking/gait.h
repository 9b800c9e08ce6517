// The timeline of a walk: footsteps in, and as functions of time the ZMP reference, the ground
// height under it, and the feet (which soles support, where the swing foot is). No dynamics
// here: the CoM comes from preview control of this ZMP reference (pattern_generator.h).
//
// Each step k has a double-support phase (the ZMP moves from the last support point to the
// stance foot, the one that stays) followed by a single-support phase (the other foot swings
// from where it is to the step's landing pose):
//   [t0, t0 + ds)          double support, ZMP: previous point -> stance sole centre (linear)
//   [t0 + ds, t0 + T)      single support on the stance foot, ZMP at its centre
//   T = step duration (the step's own, else the default), ds = double_support_ratio T; the
//   first step after standing uses ds = start_time (the ZMP leaves the middle of the feet).
// After the last step a final double support of end_time brings the ZMP back to the middle of
// the two soles, where it stays.
// The swing foot: its height rises from the lift-off pose to `height` above the higher of the
// lift-off and landing heights in the first half of the single support and comes down in the
// second (minimum jerk in each half); it moves horizontally (and turns and tilts to the landing
// surface's tilt) with a minimum-jerk profile between `vertical_fraction` of the single
// support after lift-off and the same before landing, so it leaves and lands vertically (0.3 at
// least onto or off a step of 1 cm or more that the tilt of neither sole's surface explains
// over the travel: the toe clears the stair's edge first; a slope's rise is no edge).
// The ground height under the ZMP moves like a minimum-jerk step over each step (double and
// single support: the CoM rises or falls with it on stairs and slopes, on the stance leg while
// the other foot swings, not in the short double support alone).
// Queries never allocate; Build and Replace do.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "walking/footsteps.h"

namespace ohrp::walking {

struct GaitOptions {
  double step_time = 0.8;             // [s] single + double support of one step
  double double_support_ratio = 0.1;  // [-] share of the step on both feet
  double step_height = 0.04;          // [m] swing apex above the higher end
  double vertical_fraction = 0.05;    // [-] of the single support: lift-off and landing vertical
  double start_delay = 0.8;           // [s] from a command to the first step's start when
                                      // standing: the CoM starts moving before the ZMP does
                                      // (the preview), so it needs time to start smoothly
  double start_time = 0.8;            // [s] first double support (from standing)
  double end_time = 0.8;              // [s] final double support (to standing)
  // a step from standing starts its double support with the ZMP on the swinging sole (a push
  // off it) instead of the feet's middle: the CoM crosses to the stance sole at the gait's
  // sideways speed instead of first shifting onto it (legs without an ankle roll: their CoM can
  // shift sideways over both feet only as far as the base's roll carries it)
  bool start_push = false;
  // a step from standing starts with half a single support on the swinging sole: the ZMP held
  // on it (not moved across) over a first double support of half the single support
  // ((1 - double_support_ratio) step_time / 2; start_time is not used), then on the stance sole
  // from the lift-off. With the CoM at rest beside the middle this is the second half of the
  // linear inverted pendulum's periodic orbit: the CoM crosses the middle at the orbit's speed,
  // and the sideways sway stays the orbit's d (1 - 1 / cosh(omega T_single / 2)) from the first
  // step (d the soles' half spacing) instead of the start's transient
  bool start_rock = false;
  // its mirror for the stop: after the last landing the ZMP is held on the sole that landed for
  // half a single support (the CoM comes to rest beside the middle, the orbit's first half),
  // then goes to the middle at once (the CoM comes over it at rest), end_time then standing
  bool stop_rock = false;
  double zmp_forward = 0.0;           // [m] ZMP ahead of the stance sole's centre, along the sole
  // the legs' reach, from the robot (0: not known, no step-down lowering): a step down lowers
  // the CoM over that step by as much as the landing leg needs to reach its foot with the hip
  // at most `leg_reach` from the sole (StepDownDrop)
  double leg_reach = 0.0;             // [m] hip joint to sole, the most a leg may stretch
  double hip_height = 0.0;            // [m] hip joint above the ground at the walking CoM height
  // the sole's half length (0: not known): a foot leaving an upper stair lifts its heel first
  // (toes down, as far as its toe stays above the stair: asin(apex / half length)), the trailing
  // ankle otherwise bends past its range under a CoM already over the lower stair
  double sole_half_length = 0.0;      // [m]
  // the sole's half width (0: not known) and the least gap the swinging sole keeps to the stance
  // sole in the air: where the straight path from lift-off to landing would come closer (a foot
  // turned in, or stepping past the other's toe or heel), it bends outward by d sin(pi f)
  // (f the travel, 0 at both ends), d the least in 5 mm steps that keeps the gap (SwingDetour)
  double sole_half_width = 0.0;       // [m]
  double swing_clearance = 0.01;      // [m]
};
// how far the ground under the CoM goes below the stance sole over a step whose landing lies
// `depth` [m] below the stance sole and `reach_xy` [m] from it horizontally: the landing leg's
// hip (about midway between the soles, `hip_height` above the stance sole less the drop) must
// be within `leg_reach` of the landing sole; 0 for a step that is not down, at most `depth`
double StepDownDrop(const GaitOptions& o, double depth, double reach_xy);
// how far the ground under the CoM rises above the stance sole over a step onto a stair whose
// landing lies `height` [m] above the stance sole and `reach_xy` [m] from it horizontally: as
// far as the stance (trailing) leg still reaches its sole with the hip about midway between the
// soles (it carries the robot until the next step's lift-off): sqrt(leg_reach^2 - (reach_xy/2)^2)
// - hip_height, within [0, height]; the rest of the rise comes with the next step. Raising the
// hip before the upper leg takes the weight keeps that leg's knee from folding towards the next
// riser; 0 for a step that is not up
double StepUpRise(const GaitOptions& o, double height, double reach_xy);
// "" when usable, else which option and why
std::string CheckGaitOptions(const GaitOptions& o);
// the swing foot's peak horizontal acceleration over a travel of `travel` [m] on the flat: the
// minimum-jerk profile's 10/sqrt(3) travel / T^2 over T = step_time (1 - double_support_ratio)
// (1 - 2 vertical_fraction) [m/s^2]; infinite for T <= 0
double SwingPeakAcceleration(const GaitOptions& o, double travel);
// the most a swing foot `hip_height` [m] below the hip can accelerate when the leg turns about
// the hip pitch joint of torque limit `tau_max` [N m], gravity load `tau_gravity` [N m] and
// inertia about its axis `inertia` [kg m^2] (the leg's and the rotor's):
// (tau_max - tau_gravity) hip_height / inertia [m/s^2]; infinite for no inertia
double SwingAccelerationLimit(double tau_max, double tau_gravity, double inertia, double hip_height);
// the farthest [m] a swing foot at `phase` [0, 1] of its single support may still travel when it
// lands `rest` [s] from now (Gait::AdjustStep: the remainder of the minimum-jerk travel over the
// rest at the new rate) without its horizontal acceleration exceeding `accel` [m/s^2]: the
// remainder is the share 1 - f of a whole profile (f the travel done) lasting
// Tu = rest (1 - 2 vertical) / (1 - phase), whose peak is 10/sqrt(3) d / ((1 - f) Tu^2);
// infinite for an infinite `accel`
double SwingReachDistance(double accel, double phase, double vertical, double rest);

// where everything is at one time
struct GaitState {
  Eigen::Vector3d zmp = Eigen::Vector3d::Zero();  // ZMP reference (x, y) and the ground z [m]
  double dz_ground = 0, ddz_ground = 0;           // ground height rate and acceleration
  FeetPose feet;                                  // both soles (centre of the bottom face, yaw)
  bool support[2] = {true, true};                 // left, right carries the robot
  int swing = -1;                                 // the swinging foot, -1 on both feet
  double swing_phase = 0;                         // [0, 1] through the single support
  int step = -1;                                  // index of the step under way (-1: none)
};

class Gait {
 public:
  // room for `n` steps, so that Replace does not allocate for up to that many
  void Reserve(int n) {
    steps_.reserve(n);
    pending_.reserve(n);
  }
  // standing on `feet` from time `t` (no step)
  void Start(double t, const FeetPose& feet, const GaitOptions& options);
  // replaces the steps that have not started at `now` (a step has started once its double
  // support has begun) by `steps`; they follow the last started one (or start at `now` when
  // standing). Returns the index of the first new step.
  int Replace(double now, const std::vector<Footstep>& steps);

  // moves the landing of step k, in its single support at `now`, to `xy` [m] (a stepping
  // strategy): the swing foot goes on from where it is at `now` to the new place over the rest
  // of its travel (its position continuous, no detour), the steps after it keep their places
  // and the ZMP reference follows the new stance. False (nothing changed) when step k is not in
  // single support at `now`. Allocates nothing up to Reserve's count.
  bool AdjustLanding(int k, const Eigen::Vector2d& xy, double now);
  // the same, and the landing at `t_land` [s] (in (now, the planned landing]: a swing shortened;
  // the swing goes on from its phase at `now`, continuous, over the shorter rest) and, with
  // `carry_later`, the later steps moved by the landing's change too (the walk goes on from the
  // new foothold instead of returning to the old plan). False (nothing changed) when step k is
  // not in single support at `now` or t_land is not in that range. No allocation.
  bool AdjustStep(int k, const Eigen::Vector2d& xy, double t_land, bool carry_later, double now);
  // a late touchdown (the ground lower than planned): step k's landing `delay` [s] later, the
  // swing going on from its phase at `now` (continuous, slower) and the later steps after it as
  // planned, each `delay` later; the ZMP stays on the stance sole until then. False (nothing
  // changed) when step k is not in single support at `now` or delay <= 0. No allocation.
  bool DelayLanding(int k, double delay, double now);

  // the state at `t` (any t, also in the past or after the end)
  void At(double t, GaitState* s) const;
  // ZMP reference only (for the preview samples): x, y and the ground z [m]
  Eigen::Vector3d Zmp(double t) const;

  int step_count() const { return static_cast<int>(steps_.size()); }
  const Footstep& step(int k) const { return steps_[k].step; }
  double step_begin(int k) const { return steps_[k].t0; }   // double support starts [s]
  double step_lift(int k) const { return steps_[k].t_lift; }
  double step_land(int k) const { return steps_[k].t_land; }
  // both soles after step k lands (k = -1: the start)
  FeetPose FeetAfter(int k) const;
  // index of the last step whose double support has begun at `t` (-1: none)
  int StartedBy(double t) const { return PhaseAt(t); }
  // the step `foot` stands on at `t`: its last step landed by then (null: where it started)
  const Footstep* Standing(int foot, double t) const;
  // when the ZMP reaches the middle of the final stance [s]
  double end_time() const;
  // how long the ZMP stays on the last sole that landed before it goes to the middle (stop_rock)
  double StopHold() const;
  const GaitOptions& options() const { return options_; }

 private:
  // the toes-down pitch [rad] of a foot leaving an upper stair at its top (0 when not `down`)
  double HeelLift(bool down, double apex) const;
  struct Phase {
    Footstep step;
    double t0, t_lift, t_land;
    FeetPose before;           // both soles when the step begins
    Eigen::Vector3d zmp_from;  // where the double support starts (and its ground height)
    Eigen::Vector3d zmp_to;    // the stance point
    bool hold = false;         // the ZMP stays at zmp_from until the lift-off (start_rock)
    double height;             // swing apex above the higher end [m]
    Eigen::Vector2d detour = Eigen::Vector2d::Zero();  // the swing's bend at mid-travel [m]
    // a landing moved during the swing (AdjustLanding): from where the foot was then, and its
    // travel then (the swing goes on from there); travel_from < 0: not moved
    Eigen::Vector2d moved_from = Eigen::Vector2d::Zero();
    double travel_from = -1;
    // a swing shortened (AdjustStep): from `retime_t` on, its phase goes from `retime_phase` to 1
    // at t_land; retime_t < 0: as planned
    double retime_t = -1, retime_phase = 0;
  };
  // the single support's phase (0 at lift-off, 1 at landing) of phase p at t
  static double SwingPhase(const Phase& p, double t);
  // the swing's travel (0 at lift-off, 1 at landing) of phase p at t, and its landing's
  // vertical shares
  double Travel(const Phase& p, double t) const;
  double LandingShare(const Phase& p) const;
  // a foot leaving a lower level for a stair up rolls onto its toe as it lifts (toes down about
  // the toe, at most HeelLift's angle, level again by half its travel): the trailing leg reaches
  // its sole under a hip already moving up and over the upper stair
  void ToeOff(const Phase& p, double phase, double f_travel, GaitState* s) const;
  // At's stages in a single support: the swinging foot along its travel (its place across and
  // its turn and tilt; returns the travel's share), then its height (up to the apex, down onto
  // the landing; off a stair the heel first)
  double SwingAlong(const Phase& p, double t, GaitState* s) const noexcept;
  void SwingHeight(const Phase& p, double phase, double f_travel, GaitState* s) const noexcept;
  // the height the swing lifts to before it travels (Footstep::lift_z + the apex, over a stair's
  // edge; else `top`, the apex above the highest terrain on the way)
  double LiftTop(const Phase& p, double top) const noexcept;
  // the height the swing comes down to before its vertical landing off a stair
  // (Footstep::land_z + the apex; else `top`)
  double LandTop(const Phase& p, double top) const noexcept;
  // the swing's outward bend for `step` from `before` (zero when the straight path keeps the
  // gap, or the sole's size is not known)
  Eigen::Vector2d SwingDetour(const FeetPose& before, const Footstep& step) const;
  // the last of the first `before` steps made by `foot` (null: none, it stands where it started)
  const Footstep* LastStepOf(int foot, int before) const;
  // index of the last phase with t0 <= t, -1 if none
  int PhaseAt(double t) const;
  Eigen::Vector3d StancePoint(const FeetPose& feet, int foot) const;
  Eigen::Vector3d MidPoint(const FeetPose& feet) const;

  GaitOptions options_;
  double t_start_ = 0;
  FeetPose start_;
  std::vector<Phase> steps_;
  std::vector<Footstep> pending_;  // AdjustLanding's copy of the later steps (reserved)
};

// minimum-jerk blend 0 -> 1 over s in [0, 1] (clamped), with its first and second derivatives
// with respect to s
void MinJerk(double s, double* f, double* df, double* ddf);

}  // namespace ohrp::walking
