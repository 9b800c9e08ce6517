// Small planar helpers shared by the footstep sources (internal to ohrp_walking).
#pragma once

#include <Eigen/Core>
#include <string>

#include "walking/footsteps.h"

namespace ohrp::walking {

// `a` wrapped to [-pi, pi] [rad]
double WrapAngle(double a);

// a height change between lift-off and landing that the tilt of neither sole's surface explains
// (a slope rises by its tilt over the travel): a stair's edge to clear (gait_at.cc)
bool IsStepEdge(const FeetPose& before, const Footstep& step);

// the horizontal position of `p` in the frame at `origin` turned by `yaw` about z [m]
Eigen::Vector2d InFrame(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, double yaw);

// which check of CheckStep refused a step
enum class Limit {
  kNone,
  kNumbers,
  kCross,
  kMinWidth,
  kMaxSide,
  kForward,
  kBackward,
  kTurn,
  kTurnIn,
  kClearance,
  kRise,
  kApex,
  kDuration
};

// CheckStep, also saying which check refused the step (kNone when it passes)
std::string CheckStepLimit(const FeetPose& feet, const Footstep& step, const StepLimits& limits,
                           Limit* which);

}  // namespace ohrp::walking
