// Numerical inverse kinematics of one limb (see ik.h).
//
// Each iteration solves the damped least-squares step
//   dq = J^T (J J^T + lambda^2 I)^-1 e,   lambda^2 = damping + |e|^2 / 2,
// where e stacks the position error p_WT - p and orientation_weight times the rotation vector
// of R_WT R^T (both in W), and J is the tip frame's 6 x chain Jacobian, its rotation rows
// weighted alike. The error-dependent term (Sugihara's Levenberg-Marquardt damping) keeps far
// targets and singular poses (a stretched knee) from producing huge steps, and vanishes near
// the solution so that convergence is fast there. The step is scaled down to max_step, the
// iterate clamped to the joint limits, and a joint resting on a limit that the descent
// direction J^T e pushes further out has its column removed from the next step.
//
// The analytic leg solution is not provided: the HRP-1S leg turns its yaw at the knee (HIP_R,
// HIP_P at the hip, HIP_Y at knee height), so the hip axes do not intersect and the usual
// closed form (knee from the hip-ankle distance, then the hip from the ankle-frame direction)
// does not apply; the numerical solver is used for every limb.
//
// A chain of 5 joints or fewer (H1's legs have no ankle roll) cannot reach every pose: its
// rotation rows are weighed with reduced_orientation_weight, so the position comes first and
// the orientation is the least-squares best that the position leaves (for H1: the foot's yaw
// and pitch as asked, its roll what the hip roll gives). It has converged when the position is
// within tolerance and the error's projection on the range of the Jacobian is (the rest of the
// rotation error is beyond any joint of the chain). 7 joints (redundant): the damped step is
// the minimum-norm one, nothing else changes.
#include "robot_model/ik.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ohrp::model {
namespace {

// a stall: the best error improved by less than this fraction over kStallWindow iterations
constexpr int kStallWindow = 6;
constexpr double kStallRatio = 0.01;  // [-]
// the base damping is scaled by a factor that shrinks after a step that reduced the error and
// grows after one that did not (the step is then dropped)
constexpr double kMinDampingFactor = 1e-6, kMaxDampingFactor = 1e6;  // [-]

}  // namespace

const char* IkStatusName(IkStatus s) {
  switch (s) {
    case IkStatus::kConverged:
      return "converged";
    case IkStatus::kUnreachable:
      return "unreachable";
    case IkStatus::kMaxIterations:
      return "max_iterations";
    case IkStatus::kBadInput:
      return "bad_input";
  }
  return "unknown";
}

//---------------- set-up ----------------

LimbIk::LimbIk(const Kinematics& kin, int root_body, int tip_body, const Eigen::Vector3d& p_TipT,
               const Eigen::Matrix3d& R_TipT, IkOptions options)
    : tip_body_(tip_body), p_TipT_(p_TipT), R_TipT_(R_TipT), options_(options) {
  chain_ = kin.Chain(root_body, tip_body);
  if (chain_.empty()) {
    throw std::invalid_argument(
        "LimbIk: body " + std::to_string(tip_body) + " is not a descendant of body " +
        std::to_string(root_body) + " through any of the robot's joints");
  }
  const int n = static_cast<int>(chain_.size());
  J_full_.setZero(6, kin.nv());
  J_.setZero(6, n);
  A_.setZero();
  e_.setZero();
  dq_.setZero(n);
  q_chain_.setZero(n);
  best_q_.setZero(n);
  q_min_.resize(n);
  q_max_.resize(n);
  for (int k = 0; k < n; ++k) {
    q_min_[k] = kin.robot().joints[chain_[k]].q_min;
    q_max_[k] = kin.robot().joints[chain_[k]].q_max;
  }
  q_all_.assign(kin.njoint(), 0.0);
  w_ = n < 6 ? std::min(options_.orientation_weight, options_.reduced_orientation_weight)
             : options_.orientation_weight;
  JtJ_.setZero(n, n);
  // sized once here (the solve then allocates nothing); a default-constructed LDLT moved from
  // would copy its uninitialised status (undefined behaviour, UBSan)
  ldlt_.compute(Eigen::MatrixXd::Identity(n, n));
  g_.setZero(n);
}

LimbIk LimbIk::ForSole(const Kinematics& kin, int root_body, int sole, IkOptions options) {
  // frame S in the foot body: the geom's pose, lowered by half the box's height
  const SoleMap& s = kin.soles().at(sole);
  const mjModel* m = kin.m();
  Eigen::Matrix3d R_BodyGeom;
  mjtNum R[9];
  mju_quat2Mat(R, m->geom_quat + 4 * s.geom_id);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_BodyGeom(r, c) = R[3 * r + c];
  const Eigen::Vector3d p_BodyGeom(m->geom_pos[3 * s.geom_id], m->geom_pos[3 * s.geom_id + 1],
                                   m->geom_pos[3 * s.geom_id + 2]);
  const Eigen::Vector3d p_BodyS = p_BodyGeom - s.half_size[2] * R_BodyGeom.col(2);
  return LimbIk(kin, root_body, s.body_id, p_BodyS, R_BodyGeom, options);
}

//---------------- the tip frame ----------------

Eigen::Vector3d LimbIk::p_WT(const Kinematics& kin) const {
  return kin.p_WBody(tip_body_) + kin.R_WBody(tip_body_) * p_TipT_;
}

Eigen::Matrix3d LimbIk::R_WT(const Kinematics& kin) const {
  return kin.R_WBody(tip_body_) * R_TipT_;
}

double LimbIk::Error(const Kinematics& kin, const Eigen::Vector3d& p_WT_target,
                     const Eigen::Matrix3d& R_WT_target, double* position_error,
                     double* orientation_error) {
  const Eigen::Vector3d e_p = p_WT_target - p_WT(kin);
  const Eigen::AngleAxisd e_r(Eigen::Matrix3d(R_WT_target * R_WT(kin).transpose()));
  *position_error = e_p.norm();
  *orientation_error = std::fabs(e_r.angle());
  e_.head<3>() = e_p;
  e_.tail<3>() = w_ * e_r.angle() * e_r.axis();
  return e_.norm();
}

void LimbIk::Apply(Kinematics& kin) {
  for (size_t k = 0; k < chain_.size(); ++k) q_all_[chain_[k]] = q_chain_[k];
  kin.SetJointPositions(q_all_.data());
  kin.UpdatePositions();  // the CoM velocity is not needed here
}

//---------------- solve ----------------

bool LimbIk::AtReducedOptimum(const Eigen::Matrix<double, 6, 1>& e) {
  // P e = J (J^T J)^-1 J^T e: the part of the error the chain's joints can change (to first
  // order); at the weighted least-squares best it vanishes
  JtJ_.noalias() = J_.transpose() * J_;
  JtJ_.diagonal().array() += 1e-12;  // a joint that moves nothing (a column of zeros)
  ldlt_.compute(JtJ_);
  g_.noalias() = J_.transpose() * e;
  ldlt_.solveInPlace(g_);
  const Eigen::Matrix<double, 6, 1> Pe = J_ * g_;
  return Pe.head<3>().norm() <= options_.position_tolerance &&
         Pe.tail<3>().norm() <= w_ * options_.orientation_tolerance;
}

IkResult LimbIk::Solve(Kinematics& kin, const Eigen::Vector3d& p_WT_target,
                       const Eigen::Matrix3d& R_WT_target, double* q) {
  IkResult result;
  if (!p_WT_target.allFinite() || !R_WT_target.allFinite()) return result;  // kBadInput
  const int n = static_cast<int>(chain_.size());
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(q[chain_[k]])) return result;
  }

  // start: the joints as set in kin, the chain's from q, clamped to the limits
  for (int j = 0; j < kin.njoint(); ++j) q_all_[j] = kin.q(j);
  for (int k = 0; k < n; ++k) best_q_[k] = std::clamp(q[chain_[k]], q_min_[k], q_max_[k]);
  q_chain_ = best_q_;
  Apply(kin);
  // the accepted iterate (best_q_) and its error
  double best_err = Error(kin, p_WT_target, R_WT_target, &result.position_error,
                          &result.orientation_error);
  double best_position = result.position_error, best_orientation = result.orientation_error;
  Eigen::Matrix<double, 6, 1> best_e = e_;
  double best_history[kStallWindow] = {};  // best error kStallWindow iterations ago (a ring)
  double mu = 1.0;                         // adaptive factor of the base damping
  double nu = 2.0;                         // its growth after a failed step
  bool at_best = true;                     // kin is at best_q_
  bool need_jacobian = true;

  const int col0 = kin.base_columns();
  const double w = w_;
  for (int it = 0;; ++it) {
    // the chain's weighted Jacobian at the accepted iterate (kin is there)
    if (need_jacobian) {
      kin.J_WBodyPoint(tip_body_, p_WT(kin), J_full_);
      for (int k = 0; k < n; ++k) J_.col(k) = J_full_.col(col0 + chain_[k]);
      J_.bottomRows<3>() *= w;
    }
    // done, stalled, or out of iterations
    result.iterations = it;
    if (best_position <= options_.position_tolerance &&
        (best_orientation <= options_.orientation_tolerance ||
         (n < 6 && need_jacobian && AtReducedOptimum(best_e)))) {
      result.status = IkStatus::kConverged;
      break;
    }
    if (it >= kStallWindow && best_err > (1.0 - kStallRatio) * best_history[it % kStallWindow]) {
      result.status = IkStatus::kUnreachable;
      break;
    }
    if (it >= options_.max_iterations) {
      result.status = IkStatus::kMaxIterations;
      break;
    }
    best_history[it % kStallWindow] = best_err;

    if (need_jacobian) {
      // joints on a limit that the descent direction pushes further out drop out of the step
      dq_.noalias() = J_.transpose() * best_e;
      for (int k = 0; k < n; ++k) {
        if ((best_q_[k] <= q_min_[k] && dq_[k] < 0) || (best_q_[k] >= q_max_[k] && dq_[k] > 0))
          J_.col(k).setZero();
      }
      need_jacobian = false;
    }

    // the damped least-squares step, limited in size
    A_.noalias() = J_.lazyProduct(J_.transpose());
    A_.diagonal().array() += mu * options_.damping + 0.5 * best_err * best_err;
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(A_);
    const Eigen::Matrix<double, 6, 1> y = llt.solve(best_e);
    dq_.noalias() = J_.transpose() * y;
    const double largest = dq_.cwiseAbs().maxCoeff();
    if (largest > options_.max_step) dq_ *= options_.max_step / largest;

    // the trial iterate within the limits: kept if it reduces the error (less damping next
    // time), else dropped (more damping)
    for (int k = 0; k < n; ++k) {
      q_chain_[k] = std::clamp(best_q_[k] + dq_[k], q_min_[k], q_max_[k]);
      dq_[k] = q_chain_[k] - best_q_[k];
    }
    // the reduction of the squared error that the linear model predicts for this step
    const double predicted = best_err * best_err - (best_e - J_.lazyProduct(dq_)).squaredNorm();
    Apply(kin);
    double position, orientation;
    const double err = Error(kin, p_WT_target, R_WT_target, &position, &orientation);
    if (err < best_err) {
      // Nielsen's update: less damping the better the linear model predicted the reduction
      const double rho = predicted > 0 ? (best_err * best_err - err * err) / predicted : 0.0;
      const double c = 2.0 * rho - 1.0;
      mu = std::max(mu * std::max(1.0 / 3.0, 1.0 - c * c * c), kMinDampingFactor);
      nu = 2.0;
      best_q_ = q_chain_;
      best_err = err;
      best_e = e_;
      best_position = position;
      best_orientation = orientation;
      at_best = true;
      need_jacobian = true;
    } else {
      mu = std::min(mu * nu, kMaxDampingFactor);
      nu *= 2.0;
      at_best = false;
    }
  }

  // the closest pose found, kin updated there
  if (!at_best) {
    q_chain_ = best_q_;
    Apply(kin);
  }
  result.position_error = best_position;
  result.orientation_error = best_orientation;
  for (int k = 0; k < n; ++k) q[chain_[k]] = best_q_[k];
  return result;
}

}  // namespace ohrp::model
