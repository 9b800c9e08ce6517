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
  e_.tail<3>() = options_.orientation_weight * e_r.angle() * e_r.axis();
  return e_.norm();
}

void LimbIk::Apply(Kinematics& kin) {
  for (size_t k = 0; k < chain_.size(); ++k) q_all_[chain_[k]] = q_chain_[k];
  kin.SetJointPositions(q_all_.data());
  kin.Update();
}

//---------------- solve ----------------

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
  for (int k = 0; k < n; ++k) q_chain_[k] = std::clamp(q[chain_[k]], q_min_[k], q_max_[k]);
  Apply(kin);
  double err = Error(kin, p_WT_target, R_WT_target, &result.position_error,
                     &result.orientation_error);
  double best_err = err;
  best_q_ = q_chain_;
  double best_history[kStallWindow] = {};  // best error at the last iterations (a ring)

  const int col0 = kin.base_columns();
  const double w = options_.orientation_weight;
  for (int it = 0;; ++it) {
    // done, out of iterations, or stalled
    if (result.position_error <= options_.position_tolerance &&
        result.orientation_error <= options_.orientation_tolerance) {
      result.status = IkStatus::kConverged;
      result.iterations = it;
      break;
    }
    if (it >= kStallWindow && best_err > (1.0 - kStallRatio) * best_history[it % kStallWindow]) {
      result.status = IkStatus::kUnreachable;
      result.iterations = it;
      break;
    }
    if (it >= options_.max_iterations) {
      result.status = IkStatus::kMaxIterations;
      result.iterations = it;
      break;
    }
    best_history[it % kStallWindow] = best_err;

    // the chain's weighted Jacobian at the tip frame's origin
    kin.J_WBodyPoint(tip_body_, p_WT(kin), J_full_);
    for (int k = 0; k < n; ++k) J_.col(k) = J_full_.col(col0 + chain_[k]);
    J_.bottomRows<3>() *= w;

    // joints on a limit that the descent direction pushes further out drop out of the step
    dq_.noalias() = J_.transpose() * e_;
    for (int k = 0; k < n; ++k) {
      if ((q_chain_[k] <= q_min_[k] && dq_[k] < 0) || (q_chain_[k] >= q_max_[k] && dq_[k] > 0))
        J_.col(k).setZero();
    }

    // the damped least-squares step, limited in size
    A_.noalias() = J_.lazyProduct(J_.transpose());
    A_.diagonal().array() += options_.damping + 0.5 * err * err;
    const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(A_);
    const Eigen::Matrix<double, 6, 1> y = llt.solve(e_);
    dq_.noalias() = J_.transpose() * y;
    const double largest = dq_.cwiseAbs().maxCoeff();
    if (largest > options_.max_step) dq_ *= options_.max_step / largest;

    // the next iterate within the limits
    for (int k = 0; k < n; ++k) q_chain_[k] = std::clamp(q_chain_[k] + dq_[k], q_min_[k], q_max_[k]);
    Apply(kin);
    err = Error(kin, p_WT_target, R_WT_target, &result.position_error, &result.orientation_error);
    if (err < best_err) {
      best_err = err;
      best_q_ = q_chain_;
    }
  }

  // the closest pose found, kin updated there
  if (err > best_err) {
    q_chain_ = best_q_;
    Apply(kin);
    Error(kin, p_WT_target, R_WT_target, &result.position_error, &result.orientation_error);
  }
  for (int k = 0; k < n; ++k) q[chain_[k]] = q_chain_[k];
  return result;
}

}  // namespace ohrp::model
