// Small rotations shared by the walk controller's files (internal to controllers/src).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

namespace ohrp::controllers::walk_geometry {

inline double Wrap(double a) { return std::remainder(a, 2 * M_PI); }
inline double YawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }
inline Eigen::Matrix3d Rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
inline Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
inline Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }

}  // namespace ohrp::controllers::walk_geometry
