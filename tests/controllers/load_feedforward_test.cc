// The load feed-forward (controllers/load_feedforward.h) against MuJoCo's inverse dynamics: for
// a posture at rest with the weight on the soles in given shares, the torques the joints need
// are mj_inverse's qfrc_inverse (zero velocity and acceleration; constraints and passive forces
// off: the generalised force all sources together must give) minus the soles' forces mapped by
// mj_applyFT. Recursive Newton-Euler and MuJoCo's own force mapping, against the feed-forward's
// gravity torques and Jacobian transposes. On HRP-1S and, through its profile, Unitree G1.
#include "controllers/load_feedforward.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

// qfrc_inverse's joint rows for `k`'s state with a vertical force share * m g at each sole's
// centre
std::vector<double> InverseDynamics(const model::Kinematics& k, const double share[2]) {
  mjModel* m = mj_copyModel(nullptr, k.m());
  m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_PASSIVE;
  mjData* d = mj_makeData(m);
  const model::RobotMap& robot = k.robot();
  if (robot.base_body >= 0) {
    const int adr = m->jnt_qposadr[m->body_jntadr[robot.base_body]];
    const Eigen::Vector3d p = k.p_WB();
    const Eigen::Quaterniond q = k.quat_WB();
    const double pose[7] = {p.x(), p.y(), p.z(), q.w(), q.x(), q.y(), q.z()};
    for (int i = 0; i < 7; ++i) d->qpos[adr + i] = pose[i];
  }
  for (int j = 0; j < k.njoint(); ++j) d->qpos[robot.joints[j].qpos_adr] = k.q(j);
  mj_inverse(m, d);  // qfrc_inverse: what all forces together must give (no velocity, no acceleration)
  // the soles' forces as generalised forces (mj_applyFT); the motors give the rest
  std::vector<mjtNum> external(m->nv, 0.0);
  const double weight = -m->opt.gravity[2] * k.mass();
  const int sole[2] = {k.left_sole(), k.right_sole()};
  for (int i = 0; i < 2; ++i) {
    mjtNum f[3] = {0, 0, share[i] * weight}, torque[3] = {0, 0, 0}, point[3];
    const Eigen::Vector3d p = k.p_WSole(sole[i]);
    for (int a = 0; a < 3; ++a) point[a] = p[a];
    mj_applyFT(m, d, f, torque, point, k.soles()[sole[i]].body_id, external.data());
  }
  std::vector<double> tau(k.njoint());
  for (int j = 0; j < k.njoint(); ++j) {
    const int dof = robot.joints[j].dof_adr;
    tau[j] = d->qfrc_inverse[dof] - external[dof];
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return tau;
}

// `k` at its model's first keyframe (or qpos0) with the base tilted and shifted, then checked
void ExpectInverseDynamics(model::Kinematics* k) {
  std::vector<double> q(k->njoint());
  for (int j = 0; j < k->njoint(); ++j) {
    const model::JointMap& jm = k->robot().joints[j];
    const double q0 = k->m()->nkey > 0 ? k->m()->key_qpos[jm.qpos_adr] : k->m()->qpos0[jm.qpos_adr];
    // a posture off the keyframe, within the limits
    q[j] = std::clamp(q0 + 0.05 * std::sin(1.7 * j), jm.q_min, jm.q_max);
  }
  k->SetJointPositions(q.data());
  k->SetBasePose(Eigen::Vector3d(0.1, -0.2, 0.7),
                 Eigen::Quaterniond(Eigen::AngleAxisd(0.08, Eigen::Vector3d(0.3, 1, 0.2).normalized())));
  k->Update();
  const int sole[2] = {k->left_sole(), k->right_sole()};
  ASSERT_GE(sole[0], 0);
  ASSERT_GE(sole[1], 0);
  LoadFeedforward ff(*k, sole);
  std::vector<double> tau_max(k->njoint(), 1e9), tau(k->njoint());
  for (const auto& share : std::vector<std::array<double, 2>>{{0.5, 0.5}, {1.0, 0.0}, {0.2, 0.8}}) {
    ff.Compute(*k, share.data(), tau_max.data(), tau.data());
    const std::vector<double> ref = InverseDynamics(*k, share.data());
    double largest = 0;
    for (int j = 0; j < k->njoint(); ++j) {
      largest = std::max(largest, std::abs(ref[j]));
      EXPECT_NEAR(tau[j], ref[j], 1e-9 * (1 + std::abs(ref[j])))
          << k->robot().joints[j].name << ", shares " << share[0] << "/" << share[1];
    }
    EXPECT_GT(largest, 1.0);  // the test is not of zeros
  }
  // clamped to 90 % of the limit
  std::vector<double> small(k->njoint(), 2.0);
  const double even[2] = {0.5, 0.5};
  ff.Compute(*k, even, small.data(), tau.data());
  for (int j = 0; j < k->njoint(); ++j) EXPECT_LE(std::abs(tau[j]), 0.9 * 2.0 + 1e-12);
}

TEST(LoadFeedforward, Hrp1sMatchesMuJoCosInverseDynamics) {
  std::string error;
  auto k = model::Kinematics::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml", &error);
  ASSERT_TRUE(k) << error;
  ExpectInverseDynamics(k.get());
}

TEST(LoadFeedforward, G1ThroughItsProfileMatchesMuJoCosInverseDynamics) {
  if (testing::ExternalDir().empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
  std::string error;
  auto k = model::Kinematics::Load(std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml", &error);
  ASSERT_TRUE(k) << error;
  ExpectInverseDynamics(k.get());
}

}  // namespace
}  // namespace ohrp::controllers
