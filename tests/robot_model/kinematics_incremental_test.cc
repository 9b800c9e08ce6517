// Tests that Kinematics' incremental updates (robot_model/kinematics.h: Update recomputes only
// what changed, UpdatePositions leaves the CoM velocity out, geoms and sites posed per query)
// equal MuJoCo's full pipeline bit for bit, whatever the order of the calls.
#include <gtest/gtest.h>

#include <memory>
#include <random>

#include "random_state.h"
#include "robot_model/kinematics.h"
#include "test_models.h"

namespace ohrp::model {
namespace {

using namespace testing;  // NOLINT: the test models and states

std::unique_ptr<Kinematics> Hrp1s() {
  std::string error;
  auto kin = testing::Hrp1s(&error);
  EXPECT_TRUE(kin) << error;
  return kin;
}

// Update recomputes only what changed, UpdatePositions leaves the CoM velocity out, and the
// geoms and sites are posed per query: whatever the order of calls, every query must equal
// what MuJoCo's full pipeline (mj_kinematics, mj_comPos, mj_comVel, mj_subtreeVel on the full
// model) gives for the state set, run once per change of it (positions, or velocities only),
// bit for bit (tolerance 0: the same operations in the same order)
// MuJoCo's row-major 3x3
Eigen::Matrix3d Mat3(const mjtNum* x) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(x);
}

TEST(KinematicsHrp1s, IncrementalUpdatesEqualMujocosFullPipelineExactly) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  const mjModel* m = kin->m();
  mjData* d = mj_makeData(m);
  const int base = kin->robot().base_body;
  const int qb = kin->robot().base_qpos, vb = kin->robot().base_dof;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd J(6, kin->nv()), J_com(3, kin->nv());
  Eigen::VectorXd tau(kin->nv());
  std::vector<double> dq(kin->njoint());
  Eigen::Vector3d v_WB, w_WB;
  State s = RandomState(*kin, &rng);
  // the reference keeps its own state as the setters write it (mj_kinematics normalises the
  // base quaternion in qpos, which the next velocity conversion reads)
  auto set_positions = [&] {
    const Eigen::Quaterniond quat = s.quat_WB.normalized();
    const double pose[7] = {s.p_WB.x(), s.p_WB.y(), s.p_WB.z(),
                            quat.w(),   quat.x(),   quat.y(),   quat.z()};
    for (int k = 0; k < 7; ++k) d->qpos[qb + k] = pose[k];
    for (int j = 0; j < kin->njoint(); ++j) d->qpos[kin->robot().joints[j].qpos_adr] = s.q[j];
  };
  // the full computation of the state set (without mj_kinematics when only the velocities
  // changed), w_WB turned into the base frame first
  auto reference = [&](bool positions) {
    mjtNum R[9];
    mju_quat2Mat(R, d->qpos + qb + 3);
    const Eigen::Matrix3d R_WB = Mat3(R);
    const Eigen::Vector3d w_B = R_WB.transpose() * w_WB;  // as kinematics.cc writes it
    for (int k = 0; k < 3; ++k) {
      d->qvel[vb + k] = v_WB[k];
      d->qvel[vb + 3 + k] = w_B[k];
    }
    for (int j = 0; j < kin->njoint(); ++j) d->qvel[kin->robot().joints[j].dof_adr] = dq[j];
    if (positions) mj_kinematics(m, d);
    mj_comPos(m, d);
    mj_comVel(m, d);
    mj_subtreeVel(m, d);
  };
  // every query against the reference; the CoM velocity only when `velocity` (after Update)
  auto check = [&](bool velocity, const char* what) {
    SCOPED_TRACE(what);
    for (int b = 0; b < m->nbody; ++b) {
      EXPECT_EQ(kin->p_WBody(b), Eigen::Vector3d(d->xpos + 3 * b));
      EXPECT_EQ(kin->R_WBody(b), Mat3(d->xmat + 9 * b));
    }
    for (int i = 0; i < m->nsite; ++i) {
      EXPECT_EQ(kin->p_WSite(i), Eigen::Vector3d(d->site_xpos + 3 * i));
      EXPECT_EQ(kin->R_WSite(i), Mat3(d->site_xmat + 9 * i));
    }
    for (int i = 0; i < 2; ++i) {
      const SoleMap& sole = kin->soles()[i];
      const Eigen::Matrix3d R = Mat3(d->geom_xmat + 9 * sole.geom_id);
      const Eigen::Vector3d centre(d->geom_xpos + 3 * sole.geom_id);
      EXPECT_EQ(kin->R_WSole(i), R);
      EXPECT_EQ(kin->p_WSole(i), Eigen::Vector3d(centre - sole.half_size[2] * R.col(2)));
    }
    EXPECT_EQ(kin->p_WCoM(), Eigen::Vector3d(d->subtree_com + 3 * base));
    if (velocity) {
      EXPECT_EQ(kin->v_WCoM(), Eigen::Vector3d(d->subtree_linvel + 3 * base));
    }
    // a Jacobian: MuJoCo's point Jacobian of the same body and point, in our columns
    const int foot = kin->soles()[0].body_id;
    const Eigen::Vector3d p = kin->p_WSole(0);
    kin->J_WBodyPoint(foot, p, J);
    std::vector<mjtNum> jacp(3 * m->nv), jacr(3 * m->nv);
    mj_jac(m, d, jacp.data(), jacr.data(), p.data(), foot);
    for (const JointMap& j : kin->robot().joints) {
      for (int r = 0; r < 3; ++r) {
        EXPECT_EQ(J(r, 6 + (&j - kin->robot().joints.data())), jacp[r * m->nv + j.dof_adr]);
        EXPECT_EQ(J(3 + r, 6 + (&j - kin->robot().joints.data())), jacr[r * m->nv + j.dof_adr]);
      }
    }
  };
  auto random_velocities = [&] {
    v_WB = Eigen::Vector3d(u(rng), u(rng), u(rng));
    w_WB = Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (double& x : dq) x = u(rng);
    kin->SetBaseVelocity(v_WB, w_WB);
    kin->SetJointVelocities(dq.data());
  };
  for (int trial = 0; trial < 5; ++trial) {
    // a new state, full update
    s = RandomState(*kin, &rng);
    random_velocities();
    Apply(*kin, s);
    set_positions();
    reference(true);
    check(true, "new state, Update");
    // the same values set again: nothing to recompute, still the same
    Apply(*kin, s);
    check(true, "same state again");
    // new velocities only
    random_velocities();
    kin->Update();
    reference(false);
    check(true, "new velocities");
    // the dynamics queries leave the kinematics alone
    kin->GravityTorques(tau);
    kin->J_WCoM(J_com);
    kin->Update();
    check(true, "after GravityTorques");
    // new positions without the velocity, then with it
    s = RandomState(*kin, &rng);
    kin->SetBasePose(s.p_WB, s.quat_WB);
    kin->SetJointPositions(s.q.data());
    kin->UpdatePositions();
    set_positions();
    reference(true);
    check(false, "UpdatePositions");
    kin->Update();
    check(true, "Update after UpdatePositions");
  }
  mj_deleteData(d);
}

//---------------- soles ----------------

}  // namespace
}  // namespace ohrp::model
