// The joint torques that carry the robot's weight as the stabilizer means it to be carried:
// what each joint must give for the robot to hold its current posture under gravity with its
// weight on the soles in the desired shares, sent as the commands' feed-forward so that the
// servo's PD acts on the error only instead of sagging under the load (a stance hip carrying
// the whole body sags by load / kp: on Unitree G1 at the suggested gains, 0.06 rad, enough to
// tip the body over its narrow sole).
//
// Static equilibrium of the joint rows of the floating-base equations:
//   tau = g(q) - sum_soles J_S(p_S)^T (0, 0, share_S m g)
// g(q): the gravity torques at the measured posture and estimated base orientation (MuJoCo's
// qfrc_bias at rest, Kinematics::GravityTorques); share_S: the stabilizer's desired share of the
// normal force on sole S (1 on the stance sole, 0 on a swing sole), applied at the sole's
// centre p_S; J_S(p_S): the Jacobian of the sole's body at that point. A sole in the air gets
// no force: its leg's joints carry the leg's gravity.
//
// Why desired shares and not the ankle sensors' wrenches: a feed-forward equal to the measured
// load feeds each joint's own torque back to it (the sensor measures what the joint pushes),
// an integrator without a bound that let G1 fall within seconds. The shares come from the plan
// and the stabilizer; the sensors only close the stabilizer's loops.
//
// Torques are clamped to a share of each joint's torque limit (the servo refuses a feed-forward
// above the limit). Compute allocates nothing. Nothing of a particular robot: the model, the
// estimate and the stabilizer give every number.
#pragma once

#include <Eigen/Core>

#include "robot_model/kinematics.h"

namespace ohrp::controllers {

class LoadFeedforward {
 public:
  // `sole`: the left and right soles' indices in k.soles(); sized for `k`'s model
  LoadFeedforward(const model::Kinematics& k, const int sole[2]);

  // the feed-forward torques (njoint, joint-id order) for `k`'s state (measured posture,
  // estimated base: updated by the caller) and the desired normal force shares (left, right;
  // each in [0, 1]); each clamped to +-kLimitShare * tau_max[j]. `k` is non-const for its
  // gravity torques' caches.
  void Compute(model::Kinematics& k, const double share[2], const double* tau_max,
               double* tau_ff) noexcept;

  static constexpr double kLimitShare = 0.9;

 private:
  int sole_[2];
  Eigen::VectorXd tau_;   // nv
  Eigen::MatrixXd J_;     // 6 x nv
};

}  // namespace ohrp::controllers
