// Joint angles of a walking robot from its planned CoM and feet (the last stage of the pattern
// generator): both legs by inverse kinematics (ik.h) with the base upright at a given yaw, and
// the base moved until the model's CoM is where the plan puts it. The joints outside the legs
// (arms, torso) stay as the caller set them.
//
// Method: fixed-point iterations on the base position p_WB: legs to the soles' targets with the
// base at p_WB, CoM of the whole model, p_WB += (c_target - c) scaled by the share of the mass
// that moves with the base (measured on the model at set-up). Warm-started from the last
// solution, one or two iterations per control cycle suffice.
// A leg of fewer than 6 joints (a 5-joint leg without an ankle roll: the sole's roll is the
// base's roll plus the hip roll, so a hip shifted sideways over its foot tilts the sole) is
// solved with the base's roll free (Solve's `roll`): the base's sideways position and roll
// are found by Gauss-Newton (a numerical 3 x 2 Jacobian) so that the supporting soles come out
// flat first (each roll error weighed 10 m/rad against the CoM's error) and, with the weight
// the caller gives, the CoM's sideways place is the planned one; the roll is kept within
// `max_roll`. The soles' position,
// pitch and yaw are met by the legs as before; what is left of the roll is the consequence.
// Solve allocates nothing and throws nothing.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

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
  // with the base's roll free when the legs are short (rolls_base()): `roll` [rad] about the
  // heading's forward axis (quat_WB then gives the heading), start guess and result;
  // weights[0..1] how much each sole must come out flat (1: supporting, 0: free), weights[2]
  // how much the CoM's sideways place counts against that. Legs of 6 joints: the Solve above
  // (roll left at 0)
  WalkIkResult Solve(const Eigen::Vector3d& com, const Eigen::Quaterniond& quat_WB,
                     const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2],
                     const double weights[3], double* q, Eigen::Vector3d* p_WB, double* roll,
                     double tolerance = 1e-5) noexcept;
  // a leg has fewer than 6 joints: its sole's roll follows the base's
  bool rolls_base() const { return rolls_base_; }
  double max_roll = 0.25;  // [rad] the base's roll at most (rolls_base()); chosen, not derived

  model::Kinematics& kin() { return *kin_; }
  model::LimbIk& leg(int i) { return *leg_[i]; }
  int sole(int i) const { return sole_[i]; }

 private:
  WalkIk() = default;
  model::Kinematics* kin_ = nullptr;
  std::unique_ptr<model::LimbIk> leg_[2];
  int sole_[2] = {-1, -1};
  double base_share_ = 1.0;  // d(CoM)/d(base) with the feet held [-]
  bool rolls_base_ = false;
  std::vector<double> q_try_;  // njoint: the Jacobian's trial solutions
  // the legs at the base pose (p_WB, heading R_H rolled by `roll`) from q; the residuals
  // (the soles' roll errors [rad], weighted, and the CoM's sideways error [m], weighted) and
  // the CoM error; false when a leg did not converge (r->leg says which)
  bool Evaluate(const Eigen::Vector3d& com, const Eigen::Matrix3d& R_H,
                const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2],
                const double weights[3], const Eigen::Vector3d& p_WB, double roll, double* q,
                Eigen::Vector3d* residual, Eigen::Vector3d* e_com, WalkIkResult* r) noexcept;
};

}  // namespace ohrp::walking
