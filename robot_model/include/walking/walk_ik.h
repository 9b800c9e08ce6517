// Joint angles of a walking robot from its planned CoM and feet (the last stage of the pattern
// generator): both legs by inverse kinematics (ik.h) with the base upright at a given yaw, and
// the base moved until the model's CoM is where the plan puts it. The joints outside the legs
// (arms, torso) stay as the caller set them.
//
// Method: fixed-point iterations on the base position p_WB: legs to the soles' targets with the
// base at p_WB, CoM of the whole model, p_WB += (c_target - c) scaled by the share of the mass
// that moves with the base (measured on the model at set-up). Warm-started from the last
// solution, one or two iterations per control cycle suffice.
// Solve allocates nothing and throws nothing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>

#include "robot_model/ik.h"
#include "robot_model/kinematics.h"

namespace ohrp::walking {

struct WalkIkResult {
  bool ok = false;              // both legs converged and the CoM within tolerance
  int iterations = 0;
  double com_error = 0;         // [m]
  model::IkStatus leg[2] = {model::IkStatus::kBadInput, model::IkStatus::kBadInput};
};

class WalkIk {
 public:
  // the legs from the base to the left and right soles of `kin` (which it then uses for every
  // Solve); null with `*error` when the robot has no floating base or no two soles
  static std::unique_ptr<WalkIk> Create(model::Kinematics* kin, std::string* error);

  // q (njoint, joint-id order): the start guess and the result (legs only changed);
  // p_WB: the base position, start guess and result; quat_WB: the base orientation (held);
  // the soles' targets: p_WS (centre of the bottom face) and R_WS, left then right
  WalkIkResult Solve(const Eigen::Vector3d& com, const Eigen::Quaterniond& quat_WB,
                     const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2], double* q,
                     Eigen::Vector3d* p_WB, double tolerance = 1e-5) noexcept;

  model::Kinematics& kin() { return *kin_; }
  model::LimbIk& leg(int i) { return *leg_[i]; }
  int sole(int i) const { return sole_[i]; }

 private:
  WalkIk() = default;
  model::Kinematics* kin_ = nullptr;
  std::unique_ptr<model::LimbIk> leg_[2];
  int sole_[2] = {-1, -1};
  double base_share_ = 1.0;  // d(CoM)/d(base) with the feet held [-]
};

}  // namespace ohrp::walking
