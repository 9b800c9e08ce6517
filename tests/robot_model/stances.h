// Stances shared by the footstep tests: both soles side by side, and the feet after steps.
#pragma once

#include <cmath>
#include <vector>

#include "walking/footsteps.h"

namespace ohrp::walking {

// both soles side by side at `width` [m] about (x, y) [m] with heading yaw [rad], at height z
inline FeetPose Stance(double width, double x = 0, double y = 0, double yaw = 0, double z = 0) {
  FeetPose f;
  for (int s : {kLeft, kRight}) {
    const double side = s == kLeft ? 0.5 * width : -0.5 * width;
    f.p[s] = Eigen::Vector3d(x - side * std::sin(yaw), y + side * std::cos(yaw), z);
    f.yaw[s] = yaw;
  }
  return f;
}

// the feet after all of `steps`
inline FeetPose Apply(FeetPose f, const std::vector<Footstep>& steps) {
  for (const auto& s : steps) f = After(f, s);
  return f;
}

}  // namespace ohrp::walking
