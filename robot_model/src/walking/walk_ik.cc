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

}  // namespace ohrp::walking
