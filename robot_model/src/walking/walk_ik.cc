// Legs and base from the planned CoM and feet (walk_ik.h).
#include "walking/walk_ik.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ohrp::walking {

std::unique_ptr<WalkIk> WalkIk::Create(model::Kinematics* kin, std::string* error) {
  if (!kin->floating() || kin->left_sole() < 0 || kin->right_sole() < 0) {
    *error = "walking needs a robot with a floating base and two soles (box geoms named *_SOLE)";
    return nullptr;
  }
  std::unique_ptr<WalkIk> w(new WalkIk());
  w->kin_ = kin;
  w->sole_[0] = kin->left_sole();
  w->sole_[1] = kin->right_sole();
  try {
    for (int i = 0; i < 2; ++i) {
      w->leg_[i] = std::make_unique<model::LimbIk>(
          model::LimbIk::ForSole(*kin, kin->robot().base_body, w->sole_[i]));
    }
  } catch (const std::exception& e) {
    *error = e.what();
    return nullptr;
  }
  // the share of the mass that moves with the base when the feet stay: all but the feet's
  // bodies and about half of each leg's other links; measured instead as 1 - (mass of the leg
  // chains' bodies) / 2, which is within the fixed-point iteration's tolerance of the truth
  const mjModel* m = kin->m();
  double legs = 0;
  for (int i = 0; i < 2; ++i) {
    for (int j : w->leg_[i]->chain()) legs += m->body_mass[m->jnt_bodyid[kin->robot().joints[j].joint_id]];
  }
  w->base_share_ = std::clamp(1.0 - 0.5 * legs / kin->mass(), 0.3, 1.0);
  // a leg that cannot roll its sole on its own (fewer joints than a pose has)
  w->rolls_base_ = w->leg_[0]->chain().size() < 6 || w->leg_[1]->chain().size() < 6;
  w->q_try_.assign(kin->robot().joints.size(), 0.0);
  return w;
}

WalkIkResult WalkIk::Solve(const Eigen::Vector3d& com, const Eigen::Quaterniond& quat_WB,
                           const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2], double* q,
                           Eigen::Vector3d* p_WB, double tolerance) noexcept {
  WalkIkResult r;
  constexpr int kMaxIterations = 20;
  for (int it = 0; it < kMaxIterations; ++it) {
    r.iterations = it + 1;
    kin_->SetBasePose(*p_WB, quat_WB);
    kin_->SetJointPositions(q);
    kin_->UpdatePositions();
    bool legs_ok = true;
    for (int i = 0; i < 2; ++i) {
      r.leg[i] = leg_[i]->Solve(*kin_, p_WS[i], R_WS[i], q).status;
      legs_ok = legs_ok && r.leg[i] == model::IkStatus::kConverged;
    }
    const Eigen::Vector3d e = com - kin_->p_WCoM();
    r.com_error = e.norm();
    if (!legs_ok || !std::isfinite(r.com_error)) return r;
    if (r.com_error < tolerance) {
      r.ok = true;
      return r;
    }
    *p_WB += e / base_share_;
  }
  return r;
}

namespace {
// a supporting sole's flatness before the CoM's sideways place: a roll error of 1 mrad weighs
// as 1 cm of CoM error, so that a CoM asked beyond the base roll's reach costs a tilt of the
// soles of a tenth of a mrad per mm short, not the tilt that would put it there [m/rad]
constexpr double kSoleFirst = 10.0;
}  // namespace

bool WalkIk::Evaluate(const Eigen::Vector3d& com, const Eigen::Matrix3d& R_H,
                      const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2],
                      const double weights[3], const Eigen::Vector3d& p_WB, double roll, double* q,
                      Eigen::Vector3d* residual, Eigen::Vector3d* e_com, WalkIkResult* r) noexcept {
  const Eigen::Matrix3d R_WB = R_H * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  kin_->SetBasePose(p_WB, Eigen::Quaterniond(R_WB));
  kin_->SetJointPositions(q);
  kin_->UpdatePositions();
  bool legs_ok = true;
  for (int i = 0; i < 2; ++i) {
    r->leg[i] = leg_[i]->Solve(*kin_, p_WS[i], R_WS[i], q).status;
    legs_ok = legs_ok && r->leg[i] == model::IkStatus::kConverged;
  }
  *e_com = com - kin_->p_WCoM();
  for (int i = 0; i < 2; ++i) {
    // the sole's roll about its target's forward axis
    const Eigen::Matrix3d R = R_WS[i].transpose() * kin_->R_WSole(sole_[i]);
    (*residual)[i] = kSoleFirst * weights[i] * std::atan2(R(2, 1), R(2, 2));
  }
  (*residual)[2] = weights[2] * R_H.col(1).dot(*e_com);
  return legs_ok && std::isfinite(e_com->norm());
}

WalkIkResult WalkIk::Solve(const Eigen::Vector3d& com, const Eigen::Quaterniond& quat_WB,
                           const Eigen::Vector3d p_WS[2], const Eigen::Matrix3d R_WS[2],
                           const double weights[3], double* q, Eigen::Vector3d* p_WB, double* roll,
                           double tolerance) noexcept {
  if (!rolls_base_) {
    *roll = 0;
    return Solve(com, quat_WB, p_WS, R_WS, q, p_WB, tolerance);
  }
  WalkIkResult r;
  const Eigen::Matrix3d R_H = quat_WB.toRotationMatrix();
  const Eigen::Vector3d side = R_H.col(1);
  constexpr int kMaxIterations = 20;
  constexpr double kDy = 1e-3, kDroll = 1e-3;  // the Jacobian's differences [m], [rad]
  double* q_try = q_try_.data();
  const size_t n = q_try_.size();
  Eigen::Vector3d res, res_y, res_r, e, e_try;
  WalkIkResult unused;
  for (int it = 0; it < kMaxIterations; ++it) {
    r.iterations = it + 1;
    if (!Evaluate(com, R_H, p_WS, R_WS, weights, *p_WB, *roll, q, &res, &e, &r)) {
      r.com_error = e.norm();
      return r;
    }
    r.com_error = e.norm();
    // forward and up: the base follows the CoM as in the upright solve
    const Eigen::Vector3d e_fz = e - side * side.dot(e);
    // sideways and roll: Gauss-Newton on the residuals
    std::copy(q, q + n, q_try);
    Evaluate(com, R_H, p_WS, R_WS, weights, *p_WB + kDy * side, *roll, q_try, &res_y, &e_try, &unused);
    std::copy(q, q + n, q_try);
    Evaluate(com, R_H, p_WS, R_WS, weights, *p_WB, *roll + kDroll, q_try, &res_r, &e_try, &unused);
    Eigen::Matrix<double, 3, 2> J;
    J.col(0) = (res_y - res) / kDy;
    J.col(1) = (res_r - res) / kDroll;
    const Eigen::Matrix2d A = J.transpose() * J + 1e-6 * Eigen::Matrix2d::Identity();
    Eigen::Vector2d du = -A.ldlt().solve(J.transpose() * res);
    if (!du.allFinite()) du.setZero();
    du[0] = std::clamp(du[0], -0.02, 0.02);
    du[1] = std::clamp(du[1], -0.05, 0.05);
    const double roll_new = std::clamp(*roll + du[1], -max_roll, max_roll);
    du[1] = roll_new - *roll;
    // converged: the CoM forward and up within tolerance, the sideways step and the roll's
    // (times a metre) within ten times it (the legs' own tolerance limits the differences)
    if (e_fz.norm() < tolerance && std::abs(du[0]) < 10 * tolerance && std::abs(du[1]) < 10 * tolerance) {
      r.ok = true;
      return r;
    }
    *p_WB += e_fz / base_share_ + du[0] * side;
    *roll = roll_new;
  }
  return r;
}

}  // namespace ohrp::walking
