// TEMPORARY: the footstep types only (the planner comes from branch i10-steps)
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>
namespace ohrp::walking {
enum Side { kLeft = 0, kRight = 1 };
struct Footstep {
  int foot = kLeft;
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  double yaw = 0;
  double height = -1;
  double duration = -1;
};
struct FeetPose { Eigen::Vector3d p[2]; double yaw[2]; };
}  // namespace ohrp::walking
