// The walk of the mid frame that every footstep plan is made of (internal to ohrp_walking).
//
// Step k moves the mid frame by an increment expressed in its own frame, and the step's foot
// lands at its nominal place about the new mid frame (half the width to its side, the mid frame's
// yaw), set out sideways when it would come closer to the stance sole than the clearance.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "walking/footsteps.h"

namespace ohrp::walking {

constexpr double kZero = 1e-9;    // [m or rad] a goal or a gap below this is none
constexpr int kMaxSteps = 10000;  // a plan needing more is refused

// a planar mid frame, or a per-step increment in it: x, y [m], yaw [rad]
struct Pose2 {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  double yaw = 0;
};

// the side of `foot` in its own frame: +1 left, -1 right
inline double SideSign(int foot) { return foot == kLeft ? 1 : -1; }

// how far the inward foot of a side step may go sideways: down to min_width and to the soles'
// clearance [m]
double InwardSide(const StepLimits& l);

// the first foot for a motion (y [m], yaw [rad]): the side of the larger of the two, each over
// its limit; left when there is neither
int FirstFoot(double y, double yaw, const StepLimits& l);

// "" when the start stance keeps the limits (either sole as a step beside the other), else why not
std::string StanceProblem(const FeetPose& start, const StepLimits& l);

// The walk of the mid frame from `start`'s by `inc` (step k by foot first, then alternating), then
// the closing step(s) that leave both soles nominal about the last mid frame, at the start's mid
// height; "" or why not ("step K (foot): ..."), with `*steps` as far as it went.
std::string Walk(const FeetPose& start, const std::vector<Pose2>& inc, int first,
                 const StepLimits& l, std::vector<Footstep>* steps);

}  // namespace ohrp::walking
