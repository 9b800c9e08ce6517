// ohrp identify --sensors --model: the encoders' biases from a still log of the robot on the rig
// (identify/sensors.h).
//
// Closed form. An encoder reading q_m = q + b: the servo holds the joint where gravity and its
// torque balance, tau = G(q) (at rest, no contact: MuJoCo's qfrc_bias with zero velocity), whatever
// its reference. The model's gravity torque at the readings differs from the logged torque by
//   tau - G(q_m) = G(q_m - b) - G(q_m) = -K b,   K = dG/dq at q_m (by central differences)
// to first order, so b = -K^-1 (tau - G(q_m)) over the observable joints (those whose own
// gravity stiffness |K_jj| reaches the threshold: a joint whose axis is vertical or carries little
// feels no gravity torque from its angle, and its bias is not observable this way); the others'
// biases are taken as 0. Standard errors: the torque means' (batch means) through K^-1. Not
// covered: the model's masses and centres, friction holding part of the load.
#include <mujoco/mujoco.h>

#include <Eigen/Dense>
#include <cmath>

#include "identify/sensors.h"
#include "robot_model/model.h"

namespace ohrp::identify {
namespace {

constexpr double kStep = 1e-4;  // [rad] central differences

// the gravity torque of each logged joint at `q` (per joint), the rest of the posture as set
void Gravity(const mjModel* m, mjData* d, const std::vector<int>& qadr, const std::vector<int>& dof,
             const std::vector<double>& q, std::vector<double>* g) {
  for (size_t k = 0; k < q.size(); ++k) d->qpos[qadr[k]] = q[k];
  mju_zero(d->qvel, m->nv);
  mj_forward(m, d);
  g->resize(q.size());
  for (size_t k = 0; k < q.size(); ++k) (*g)[k] = d->qfrc_bias[dof[k]];
}

}  // namespace

bool EstimateEncoderBias(const JointModel& model_in, double min_stiffness, SensorEstimates* s,
                         std::string* error) {
  auto scene = model::Scene::Load(model_in.model, error);
  if (!scene || !scene->Reset(model_in.keyframe, error)) return false;
  mjModel* m = scene->m();
  mjData* d = scene->d();
  const size_t n = s->joints.size();
  std::vector<int> qadr(n), dof(n);
  for (size_t k = 0; k < n; ++k) {
    const int j = mj_name2id(m, mjOBJ_JOINT, s->joints[k].c_str());
    if (j < 0) return *error = s->joints[k] + ": " + model_in.model + " has no such joint", false;
    if (!std::isfinite(s->joint_tau[k].value))
      return *error = "joint " + s->joints[k] + ": no tau_" + s->joints[k] + " column: the encoder "
                      "bias needs the joints' torques", false;
    qadr[k] = m->jnt_qposadr[j], dof[k] = m->jnt_dofadr[j];
  }
  std::vector<double> g0, gp, gm, q = s->joint_mean;
  Gravity(m, d, qadr, dof, q, &g0);
  if (d->ncon > 0)
    return *error = "the model at the logged posture touches something (" + std::to_string(d->ncon) +
                    " contacts): the encoder bias needs the robot on the rig, nothing touching", false;
  Eigen::MatrixXd K(n, n);  // K(i, k) = dG_i / dq_k
  for (size_t k = 0; k < n; ++k) {
    q[k] = s->joint_mean[k] + kStep;
    Gravity(m, d, qadr, dof, q, &gp);
    q[k] = s->joint_mean[k] - kStep;
    Gravity(m, d, qadr, dof, q, &gm);
    q[k] = s->joint_mean[k];
    for (size_t i = 0; i < n; ++i) K(i, k) = (gp[i] - gm[i]) / (2 * kStep);
  }
  std::vector<int> obs;
  s->gravity_stiffness.assign(n, 0.0);
  s->encoder_observable.assign(n, false);
  s->encoder_bias.assign(n, Stat{NAN, NAN});
  for (size_t k = 0; k < n; ++k) {
    s->gravity_stiffness[k] = -K(k, k);
    if (std::fabs(K(k, k)) >= min_stiffness) obs.push_back(static_cast<int>(k)), s->encoder_observable[k] = true;
  }
  const int no = static_cast<int>(obs.size());
  if (no == 0) return true;
  Eigen::MatrixXd Ko(no, no);
  Eigen::VectorXd r(no), var(no);
  for (int a = 0; a < no; ++a) {
    r(a) = s->joint_tau[obs[a]].value - g0[obs[a]];
    var(a) = s->joint_tau[obs[a]].se * s->joint_tau[obs[a]].se;
    for (int b = 0; b < no; ++b) Ko(a, b) = K(obs[a], obs[b]);
  }
  const Eigen::MatrixXd inv = Ko.fullPivLu().inverse();
  const Eigen::VectorXd bias = -inv * r;
  const Eigen::MatrixXd cov = inv * var.asDiagonal() * inv.transpose();
  for (int a = 0; a < no; ++a) s->encoder_bias[obs[a]] = {bias(a), std::sqrt(cov(a, a))};
  return true;
}

}  // namespace ohrp::identify
