// The fall watch: every controller program decides from the robot's own sensors whether the
// robot has fallen, and a fall ends the run with exit code kExitFell (runner.h) and a message
// that says when (producer time, cycle) and why. The runner owns it, so every controller gets
// it; a controller that knows its robot's model narrows the limits (Controller::fall_limits).
//
// Two causes, each one a sustained condition (a single noisy sample never trips the watch):
//   tilt      the base's tilt from upright (the controller's estimate when it gives one, else
//             the IMU's orientation quat_WI: the angle between its z axis and the world's up)
//             beyond `max_tilt` for `tilt_time`.
//   unloaded  the feet's force/torque sensors together carry less than `unloaded_fraction` of
//             the robot's weight (total_mass of the segment header times g) for
//             `unloaded_time`, after they carried at least `armed_fraction` of it once (a robot
//             lowered onto the ground, or held in the air, is not "fallen" before it stood).
//             The magnitude of each sensor's force is used, so the sensor frames' tilt does not
//             matter.
//   collapsed the controller's estimate of its CoM's height over its lower sole (a controller
//             with a state estimator: balance, walk) below `min_com_height` for `tilt_time`: the
//             robot crumpled without tilting (its knees gave way).
// The defaults hold for any humanoid without its geometry (DefaultFallLimits); with the model,
// FallLimitsFor derives them from the stance's CoM height and the soles (balance, walk).
// Update does not allocate, throw or log.
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "shm_bridge/layout.h"

namespace ohrp::controllers {

struct FallLimits {
  double max_tilt = 0.0;           // [rad] base tilt from upright
  double tilt_time = 0.0;          // [s] sustained this long
  double unloaded_fraction = 0.0;  // [-] of the weight carried by the feet, below: unloaded
  double unloaded_time = 0.0;      // [s] sustained this long
  double armed_fraction = 0.0;     // [-] of the weight the feet must have carried once
  double min_com_height = 0;       // [m] 0: no collapse check
  int feet[2] = {-1, -1};          // force sensors of the feet (header order); -1: every sensor
  int imu = 0;                     // the IMU whose orientation gives the tilt
  std::string basis;               // how the limits were derived, for the start message
};

// Without the robot's geometry: a tilt of 45 deg (no humanoid's sole reaches as far from its
// CoM's vertical as the CoM is high, tan 45 deg = 1) for 0.2 s; the feet below 20 % of the
// weight for 0.5 s after they carried half of it.
FallLimits DefaultFallLimits();

// From the robot: a CoM `com_height` [m] above the soles over a support that reaches
// `support_reach` [m] from the CoM's vertical (the sole's half length): the tilt at which the CoM
// passes the edge of the support is atan(reach / height); the robot has fallen at twice that
// plus `upper_body_tilt` [rad] (what the controller itself may tilt the IMU by, e.g. the hip
// strategy's torso offsets), sustained for the pendulum's time constant sqrt(height / g); the
// feet unloaded for twice that; collapsed when the CoM is below half its stance height.
FallLimits FallLimitsFor(double com_height, double support_reach, double upper_body_tilt);

enum class FallCause { kNone, kTilt, kUnloaded, kCollapsed };
const char* FallCauseName(FallCause c);

struct FallEvent {
  FallCause cause = FallCause::kNone;
  double time = 0;        // producer time at which the condition had lasted long enough [s]
  uint64_t cycle = 0;     // the sensor block's cycle then
  double since = 0;       // producer time at which the condition began [s]
  double value = 0;       // tilt [rad], the feet's load [N] or the CoM's height [m] then
  double limit = 0;       // max_tilt [rad], the unloaded load [N] or min_com_height [m]
};

class FallWatch {
 public:
  // Sets the watch up for the robot of `header`. Returns "" when both checks are on, else a note
  // of what is off and why (no IMU, no force sensor, no mass, limits that are not finite); the
  // watch then runs what it can.
  std::string Configure(const shm::SegmentHeader& header, const FallLimits& limits);
  // One sensor block; `base_tilt` [rad] is the controller's estimate of the base's tilt (NaN:
  // none, the IMU's is used), `com_height` [m] its estimate of the CoM's height over its lower
  // sole (NaN: none). True once the robot has fallen (latched).
  bool Update(const shm::SensorBlock& s, double base_tilt,
              double com_height = std::numeric_limits<double>::quiet_NaN()) noexcept;

  bool fallen() const { return event_.cause != FallCause::kNone; }
  const FallEvent& event() const { return event_; }
  bool armed() const { return armed_; }
  const FallLimits& limits() const { return limits_; }
  double weight() const { return weight_; }
  // "the robot fell at t = 3.215 s (cycle 643): base tilt 37.2 deg > 18.4 deg since t = 2.9 s";
  // `tilt_from`: what the tilt was measured from (Controller::tilt_reference)
  std::string Describe(const char* tilt_from = "upright") const;
  // what the watch checks, for the start message: "fall watch: tilt > 18.4 deg for 0.27 s ..."
  std::string Summary() const;

 private:
  double Tilt(const shm::SensorBlock& s, double base_tilt) const noexcept;
  double FeetLoad(const shm::SensorBlock& s) const noexcept;

  FallLimits limits_;
  bool tilt_on_ = false, load_on_ = false;
  int nforce_ = 0;
  double weight_ = 0;          // [N]
  bool armed_ = false;
  double tilt_since_ = -1, unloaded_since_ = -1, low_since_ = -1;  // [s], -1: the condition does not hold
  FallEvent event_;
};

}  // namespace ohrp::controllers
