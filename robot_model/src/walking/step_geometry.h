// Small planar helpers shared by the footstep sources (internal to ohrp_walking).
#pragma once

#include <Eigen/Core>

namespace ohrp::walking {

// `a` wrapped to [-pi, pi] [rad]
double WrapAngle(double a);

// the horizontal position of `p` in the frame at `origin` turned by `yaw` about z [m]
Eigen::Vector2d InFrame(const Eigen::Vector3d& p, const Eigen::Vector3d& origin, double yaw);

}  // namespace ohrp::walking
