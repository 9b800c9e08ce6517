// Checks on a walk, measured from the base's pose in sim_host's data log (columns base_x,
// base_y, base_qw, base_qx, base_qy, base_qz; world frame, see sim_host/recorder.h):
//   goal_reached   the base's final pose relative to its initial one, in the initial heading
//                  frame (x forward, y left, yaw unwrapped over the run), against a goal
//   average_speed  the base's horizontal distance from start to end over the time it moved
// The scenario keys are listed in check_keys.h. SI units: metres, seconds, radians (degrees
// where a key says _deg).
#pragma once

#include <vector>

#include "runner/checks.h"

namespace ohrp::runner {

// The heading (rotation about the world's z) of the orientation (w, x, y, z), in (-pi, pi]:
// atan2(2 (w z + x y), 1 - 2 (y^2 + z^2)) [rad]; the quaternion need not be unit.
double YawOf(double qw, double qx, double qy, double qz);

// The base's heading at each row of the log, unwrapped (no jump of 2 pi between rows: a turn of
// 360 deg ends at 2 pi), starting in (-pi, pi]. Empty when the log lacks the base quaternion.
std::vector<double> UnwrappedYaw(const datalog::Table& log);

// Pose of the last row relative to the first, in the frame of the first row's heading.
struct RelativePose {
  double x = 0;    // [m] forward, along the initial heading
  double y = 0;    // [m] left
  double yaw = 0;  // [rad] heading change, unwrapped over the run
};

// The base's final pose relative to its pose at the first row at or after `from` [s] (the first
// row when the log has no time column); false with `*error` when no row is left or the log
// lacks the base columns.
bool FinalRelativePose(const datalog::Table& log, RelativePose* out, std::string* error, double from = 0);

// When the base moved: the first time it is `threshold` [m] from its start (horizontally) and,
// from then on, the first time it is within `threshold` of its final position.
struct Motion {
  double distance = 0;   // [m] horizontal, start to end
  double start = 0;      // [s]
  double end = 0;        // [s]
  bool started = false;  // it went `threshold` from its start
};
bool MeasureMotion(const datalog::Table& log, double threshold, Motion* out, std::string* error);

// The checks (keys in check_keys.h).
CheckResult GoalReached(const CheckSpec& spec, const datalog::Table& log);
CheckResult AverageSpeed(const CheckSpec& spec, const datalog::Table& log);

}  // namespace ohrp::runner
