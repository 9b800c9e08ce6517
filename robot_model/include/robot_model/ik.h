// Inverse kinematics of one limb: the joints of the chain from a root body (held where it is,
// e.g. the base) to a tip frame, solved so that the tip frame reaches a target pose.
//
// Numerical: damped least squares (Levenberg-Marquardt on the 6-D pose error, damping adapted
// to the error), steps limited in size, joint limits respected by clamping each iterate (a joint
// at its limit drops out of the next step). The base pose and the joints outside the chain are
// those set in the Kinematics object; Solve changes only the chain's entries of `q`.
// A step that does not reduce the error is dropped and the damping raised (Nielsen's rule), so
// the error never grows; when the best error improves by less than 1 % over 6 iterations the
// target is declared unreachable. The solver is local: from a start far from the target it may
// stop in a local minimum against a joint limit (kUnreachable); start from a nearby pose (e.g.
// the previous cycle's solution). No analytic leg solution is provided (see ik.cc).
//
// Per-call work allocates nothing: the scratch matrices are sized by the constructor.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "robot_model/kinematics.h"

namespace ohrp::model {

struct IkOptions {
  int max_iterations = 50;
  double position_tolerance = 1e-5;     // [m]
  double orientation_tolerance = 1e-5;  // [rad]
  double damping = 1e-4;                // base Levenberg-Marquardt damping, lambda^2 =
                                        // mu damping + |e|^2 / 2 with mu adapted from 1 [m^2]
  double max_step = 0.3;                // largest joint change per iteration [rad or m]
  double orientation_weight = 1.0;      // weight of the rotation error against position [m/rad]
  // a chain of fewer than 6 joints (e.g. a 5-joint leg without ankle roll) cannot reach every
  // pose: its rotation error is weighed with at most this [m/rad], so that the position comes
  // first and the orientation is met as far as the chain can (the least-squares best); it has
  // converged when the position is within tolerance and what is left of the weighted error is
  // beyond the chain's reach (its projection on the range of the Jacobian within tolerance)
  double reduced_orientation_weight = 0.002;
};

enum class IkStatus {
  kConverged,      // within both tolerances (a chain of fewer than 6 joints: the position
                   // within tolerance, the orientation the nearest the chain can reach)
  kUnreachable,    // stalled with an error above tolerance: the target is out of reach (or
                   // beyond the joint limits); q holds the closest pose found
  kMaxIterations,  // still improving when the iterations ran out
  kBadInput,       // non-finite target or joints
};
const char* IkStatusName(IkStatus s);

struct IkResult {
  IkStatus status = IkStatus::kBadInput;
  int iterations = 0;            // steps tried (each one Kinematics::UpdatePositions)
  double position_error = 0;     // |p_WT - p_W(tip)| at the end [m]
  double orientation_error = 0;  // angle of R_WT^T R_W(tip) at the end [rad]
};

class LimbIk {
 public:
  // The limb from `root_body` (exclusive) to the frame T fixed on `tip_body`, with pose
  // p_TipT / R_TipT in the tip body's frame. Throws std::invalid_argument when tip is not a
  // descendant of root or the chain has no joint (set-up only).
  LimbIk(const Kinematics& kin, int root_body, int tip_body,
         const Eigen::Vector3d& p_TipT = Eigen::Vector3d::Zero(),
         const Eigen::Matrix3d& R_TipT = Eigen::Matrix3d::Identity(), IkOptions options = {});
  // The limb ending at a sole's frame S (kinematics.h), rooted at `root_body`.
  static LimbIk ForSole(const Kinematics& kin, int root_body, int sole, IkOptions options = {});

  // Solves for the chain's joints. `q` (njoint, joint-id order) is the starting guess and
  // receives the result; `kin` is left updated at the result, without the CoM velocity
  // (Kinematics::UpdatePositions; call kin.Update() for it). Never allocates or throws.
  IkResult Solve(Kinematics& kin, const Eigen::Vector3d& p_WT, const Eigen::Matrix3d& R_WT,
                 double* q);

  const std::vector<int>& chain() const { return chain_; }
  // the tip frame's current pose (after kin.Update())
  Eigen::Vector3d p_WT(const Kinematics& kin) const;
  Eigen::Matrix3d R_WT(const Kinematics& kin) const;

 private:
  int tip_body_;
  Eigen::Vector3d p_TipT_;
  Eigen::Matrix3d R_TipT_;
  IkOptions options_;
  // the weighted 6-D error (position; orientation_weight times the rotation vector) of the
  // tip at kin's last Update, and its two norms
  double Error(const Kinematics& kin, const Eigen::Vector3d& p_WT, const Eigen::Matrix3d& R_WT,
               double* position_error, double* orientation_error);
  // sets the chain's joints from q_chain_ and updates kin's positions
  void Apply(Kinematics& kin);
  // a chain of fewer than 6 joints at the least-squares best of the weighted error `e`
  // (J_ at the same pose): the error's projection on the range of J_ within the tolerances
  bool AtReducedOptimum(const Eigen::Matrix<double, 6, 1>& e);

  std::vector<int> chain_;       // segment joint ids, root outwards
  Eigen::MatrixXd J_full_;       // 6 x nv
  Eigen::MatrixXd J_;            // 6 x chain
  Eigen::Matrix<double, 6, 6> A_;  // J J^T + lambda^2 I
  Eigen::VectorXd dq_;           // chain
  Eigen::Matrix<double, 6, 1> e_;  // weighted error
  Eigen::VectorXd q_chain_, best_q_, q_min_, q_max_;  // chain
  double w_ = 1.0;               // the orientation weight used (reduced for a short chain)
  Eigen::MatrixXd JtJ_;          // chain x chain (a short chain's range projection)
  Eigen::LDLT<Eigen::MatrixXd> ldlt_;
  Eigen::VectorXd g_;            // chain
  std::vector<double> q_all_;    // njoint, the joints as set in kin plus the chain's
};

}  // namespace ohrp::model
