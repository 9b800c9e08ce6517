// Footsteps: where the soles land, the limits a step must keep, and the plans that turn a
// command (a relative goal, a velocity, a stop) into a list of steps.
//
// Units are SI (m, rad, s). Poses are in the world frame W (z up); a sole's pose is the centre of
// its bottom face and its yaw about z. Planning code: called at start or on a new command, never
// per control cycle (it allocates).
//
// Conventions shared by every function here:
//  - a step is made by the foot `Footstep::foot`; the other foot is the stance foot, and every
//    limit is measured in the stance foot's frame (x forward along its yaw, y to its left);
//  - "outward" is away from the stance foot (+y for the left foot, -y for the right foot);
//  - a turn is "out" when the landing foot's toes point away from the stance foot (the left foot
//    turning left, the right foot turning right) and "in" (toes in) otherwise.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

namespace ohrp::walking {

enum Side { kLeft = 0, kRight = 1 };

// "left" or "right"
const char* SideName(int foot);

// Where one sole lands: the centre of the sole's bottom face, and its yaw, in W.
struct Footstep {
  int foot = kLeft;                             // the foot that swings and lands here
  Eigen::Vector3d p = Eigen::Vector3d::Zero();  // [m] (z: the surface height under the sole)
  double yaw = 0;                               // [rad]
  double height = -1;    // swing apex above the higher of lift-off and landing [m]; <0: default
  double duration = -1;  // the step's time, single + double support [s]; <0: default
  // the surface's tilt under the sole, in W: its normal is Rx(roll) Ry(pitch) e_z; the sole
  // lands parallel to it (terrain.h fills it from a scene) [rad]
  double roll = 0, pitch = 0;
  // where the sole touches the surface, in the sole's frame (x along it, y across): the centre
  // of that region and its half sizes; negative half sizes: the whole sole (terrain.h fills it
  // for a sole resting across an edge) [m]
  Eigen::Vector2d contact_centre = Eigen::Vector2d::Zero();
  Eigen::Vector2d contact_half = Eigen::Vector2d(-1, -1);
  // the highest terrain under the sole on its way from lift-off to landing (start frame; terrain.h
  // fills it from a scene): the swing's apex (`height`) is above the higher of it and the two
  // ends, whoever wrote the step [m]; below any ground: none known
  double clear_z = -1e9;
  // the highest terrain under the sole over the first half of its way (the lift-off's own
  // footprint left out; terrain.h fills it): over a stair's edge the swing first rises above it
  // and goes on up to the apex over the first half of its travel, so that a foot stepping over a
  // stair onto the next (one foot per stair) does not climb the whole height behind the hip [m];
  // below any ground: none known (the swing rises to its apex before it travels)
  double lift_z = -1e9;
  // the same over the second half of its way (the landing's own footprint left out): off a
  // stair's edge the swing comes down to above it over the second half of its travel, before
  // its vertical landing, so that a foot stepping past a stair onto the one below does not hang
  // the whole height above the hip [m]; below any ground: none known
  double land_z = -1e9;
};

// Both soles now (index kLeft, kRight).
struct FeetPose {
  Eigen::Vector3d p[2];  // sole centres in W [m]
  double yaw[2];         // [rad]
  double roll[2] = {0, 0}, pitch[2] = {0, 0};  // the soles' tilt (Footstep::roll, pitch) [rad]
};

// The mid frame of a stance: midpoint of the soles (x, y, z mean), yaw the mean of the yaws.
struct Frame2 {
  Eigen::Vector3d p;  // [m]
  double yaw;         // [rad]
};

// The mid frame of `feet` (the yaw mean is taken on the circle: soles at +-179 deg give 180 deg).
Frame2 MidFrame(const FeetPose& feet);

// The feet after `step`: the swinging foot's sole at the step's pose, the other unchanged.
FeetPose After(const FeetPose& feet, const Footstep& step);

// The limits one step must keep. Defaults: a small adult-sized humanoid; the caller sets `width`
// (and the sole size) from its robot.
struct StepLimits {
  double max_forward =
      0.25;  // [m] landing foot ahead of the stance foot, in the stance foot's frame
  double max_backward = 0.10;  // [m] behind it
  double width = 0.16;         // nominal distance between the sole centres, side by side [m]
                               // (the planner is given the robot's, from its stance)
  double max_side = 0.10;      // [m] outward beyond `width`
  double min_width = 0.12;     // [m] inward limit: no closer (lateral, stance frame) than this
  double max_turn = 0.35;      // [rad] yaw change of the landing foot against the stance foot
  double max_turn_in = 0.15;   // [rad] when the landing foot turns towards the stance foot
                               // (toes in), where the soles would collide
  // [m] the most a velocity walk's forward stride changes from one step to the next (from and
  // to standing: the first steps lengthen, the last shorten); infinite: at once
  double max_stride_change = INFINITY;
  Eigen::Vector2d sole_half_size{0.11, 0.065};  // [m] for the no-overlap check (x along the sole)
  double clearance = 0.02;                      // [m] least gap between the two soles' rectangles
  // the physics of one step (the walk derives them from its robot: docs/footsteps.md); the
  // defaults check nothing. A step's own height and duration (when it gives them, >= 0) and its
  // height change against the stance sole are checked.
  double max_rise = INFINITY;      // [m] |landing z - stance sole z|
  double max_apex = INFINITY;      // [m] swing apex (Footstep::height)
  double min_duration = 0;         // [s] step time (Footstep::duration)
  double max_duration = INFINITY;  // [s]
  std::string physics_basis;       // where these come from, said with a refusal
};

// "" when the limits are usable, else which one is not (negative, NaN, min_width > width, ...).
std::string CheckLimits(const StepLimits& limits);

// The least distance between the two soles' rectangles seen from above when `foot` stands at
// (p, yaw) and the other foot at (q, yaw_q) [m]; negative (minus the depth along the separating
// axis of least overlap) when they overlap.
double SoleGap(const Eigen::Vector3d& p, double yaw, const Eigen::Vector3d& q, double yaw_q,
               const StepLimits& limits);

// "" when `step` may follow the stance given (`feet` = where both soles are before the step),
// else why not, naming the limit, the value and the allowed range. Checked, in this order: the
// step's numbers (foot 0 or 1, finite pose), crossing (landing on the stance foot's other side),
// min_width, width + max_side, max_forward, max_backward, max_turn, max_turn_in, the clearance
// between the soles. A tolerance of 1e-9 (m or rad) is allowed on every limit.
std::string CheckStep(const FeetPose& feet, const Footstep& step, const StepLimits& limits);

// Checks a whole sequence from `start`: "" or "step K (left): why" for the first failing step
// (K counted from 1).
std::string CheckSteps(const FeetPose& start, const std::vector<Footstep>& steps,
                       const StepLimits& limits);

// `step` moved the least into the planar limits of CheckStep against the stance of `feet`
// (used where a step planned earlier is moved at run time, e.g. by a correction of the walk's
// frame, and may have come too close to the stance sole): its turn clamped to max_turn_in ..
// max_turn, its position in the stance foot's frame clamped to min_width .. width + max_side
// beside it and max_backward .. max_forward ahead, then set out sideways by the least amount
// (2 mm scan, then bisection) that keeps the clearance between the soles, turned parallel to
// the stance sole if no lateral place within width + max_side does. Height, tilt, duration and
// apex are kept. Returns how far the sole's centre moved [m] (0: it kept the limits; the yaw
// change is in step->yaw). Allocates nothing (a real-time path may call it).
double FitStep(const FeetPose& feet, Footstep* step, const StepLimits& limits);

// Go to a goal (x, y, yaw) given in the start's mid frame [m, m, rad] (a yaw beyond +-pi is
// taken the short way round): the fewest steps within the limits that this walk finds (the mid
// frame moves by per-step increments in its own frame, each foot taking its share: the outward
// foot the side step, the inward foot what min_width and the soles leave; the foot turning out
// max_turn, the other max_turn_in; step counts are tried upwards from a lower bound). For a goal
// straight ahead, to the side or a turn on the spot that is the least the limits allow; a walk
// that turned first could need fewer for a combined goal. The first foot is chosen by the
// direction (moving/turning left: left foot first; the other only when it needs fewer steps),
// ending with both feet side by side at `limits.width` around the goal (a closing step). A goal of
// 0 (below 1e-9): no steps. Every step passes CheckStep; a foot that would touch the other while
// turning is set out sideways by the least amount that keeps the clearance. Steps are on the
// start's mid-frame height, with default height and duration. Empty with `*error` (when non-null)
// when no plan within 10000 steps keeps the limits (bad limits, a start stance that breaks them).
std::vector<Footstep> PlanToGoal(const FeetPose& start, double x, double y, double yaw,
                                 const StepLimits& limits, std::string* error = nullptr);

// Walk at a velocity (vx, vy in the mid frame [m/s], yaw rate [rad/s]) for `time` seconds with
// steps of `step_time` (round(time / step_time) steps, at least one when time > 0), then a closing
// step; a velocity beyond the limits is reduced to them (said through `*note` when non-null). The
// first foot is chosen as in PlanToGoal; each step's duration is `step_time`. The mid frame moves
// in its own frame by vx * step_time per step and by 2 (vy, wz) * step_time per pair of steps (the
// foot on the side of the motion taking the larger share): after the walk it has covered the
// commanded displacement within one step. Where turning and walking together would break a limit
// (the soles' clearance), the whole walk is slowed by steps of 10 % until it keeps them (said
// through `*note`). With a finite `limits.max_stride_change` the forward stride grows from
// standing and shrinks to the closing step by at most that per step (said through `*note`; the
// walk then covers less than vx * time). Empty, with `*note`, when the numbers are not finite, step_time <= 0, time <
// 0, the limits are unusable or the start stance breaks them; empty without a note for time 0.
std::vector<Footstep> PlanVelocity(const FeetPose& start, double vx, double vy, double wz,
                                   double time, double step_time, const StepLimits& limits,
                                   std::string* note = nullptr);

// `count` steps drawn at random (seeded: the same seed gives the same steps) within the planar
// limits, alternating feet from a random first foot: each landing drawn uniformly in the stance
// sole's frame over max_backward .. max_forward ahead, min_width .. width + max_side beside it and
// -max_turn_in .. max_turn turned, set out sideways where the soles would come closer than the
// clearance (FitStep) and drawn again (up to 100 times) if it still breaks a limit. With
// probability `stop_share` a step is instead a stop (the other foot closes beside the last, as
// PlanStop). Ends with the feet side by side. Every step passes CheckStep; steps are at the stance
// sole's height with default height and duration. Empty with `*error` for a count outside
// [0, 10000], a share outside [0, 1], unusable limits or a start stance that breaks them.
std::vector<Footstep> PlanRandom(const FeetPose& start, int count, unsigned seed,
                                 const StepLimits& limits, double stop_share = 0.15,
                                 std::string* error = nullptr);

// The step(s) that bring the feet side by side from `feet` when the last step was by `last_foot`
// (stopping a velocity walk: the other foot closes, at `limits.width` beside the last foot and
// parallel to it). Empty when the feet are already side by side (within 1e-9) or `last_foot` is
// neither kLeft nor kRight.
std::vector<Footstep> PlanStop(const FeetPose& feet, int last_foot, const StepLimits& limits);

}  // namespace ohrp::walking
