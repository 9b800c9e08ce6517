// What an OpenHRP VRML file does not say and MuJoCo needs: torque limits, the ranges of joints
// without llimit/ulimit, the soles, the order of the force sensors, the half-sitting pose, and
// the springs of OpenHRP's rubber bushes. The values are those of the SampleRobot (HRP-1S class,
// mjcf/hrp1s/README.md explains them); joints of other robots match no entry and get the
// fallbacks below.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace ohrp::vrml {

// torque limit [N m or N] of a motor by joint name; 0 when the profile has none (no limit)
double TorqueLimit(const std::string& joint);

// range [rad or m] assumed for a joint the file gives no llimit/ulimit
std::pair<double, double> AssumedRange(const std::string& joint);

// joint angle of the `halfsit` keyframe [rad]; 0 for joints not listed
double HalfSitting(const std::string& joint);

// foot link (Joint DEF name) -> name of its sole geom (the lowest Box of the link and the
// passive links below it)
const std::vector<std::pair<std::string, std::string>>& Soles();

// force sensors listed first, in this order (right ankle first); others after, by sensorId
int ForceSensorRank(const std::string& sensor);

inline constexpr double kJointDamping = 0.1;          // motor joints [N m s/rad]
inline constexpr const char* kFriction = "1 0.005 0.0001";  // soles and scenery

// a passive Joint whose name contains "BUSH" is a rubber bush: a spring-damper about its zero,
// stiffness from the file's `stiffness` field when it sets one, else these values (hrpsys'
// bush customizers use the same: 1e6 N/m, 1e3 N s/m, 2.5e3 N m/rad, 2.5 N m s/rad)
inline constexpr double kBushStiffnessLinear = 1.0e6;   // [N/m]
inline constexpr double kBushDampingLinear = 1.0e3;     // [N s/m]
inline constexpr double kBushStiffnessAngular = 2.5e3;  // [N m/rad]
inline constexpr double kBushDampingAngular = 2.5;      // [N m s/rad]

}  // namespace ohrp::vrml
