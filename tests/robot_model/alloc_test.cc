// Tests that the per-cycle calls of robot_model/kinematics, robot_model/ik and
// robot_model/estimator allocate nothing:
// this binary replaces malloc and its relatives (count_allocations.h), so every heap allocation
// (operator new, Eigen, MuJoCo) made while counting is seen.
#include <gtest/gtest.h>

#include <vector>

#include "count_allocations.h"
#include "robot_model/estimator.h"
#include "robot_model/ik.h"
#include "robot_model/kinematics.h"
#include "test_models.h"

namespace ohrp::model {
namespace {

#if defined(OHRP_CAN_COUNT)

using ohrp::testing::Allocations;

TEST(Allocation, TheCounterSeesAnAllocation) {
  std::vector<double>* v = nullptr;
  EXPECT_GT(Allocations([&] { v = new std::vector<double>(100); }), 0);
  delete v;
  Eigen::MatrixXd* M = nullptr;
  EXPECT_GT(Allocations([&] { M = new Eigen::MatrixXd(7, 7); }), 0);
  delete M;
  // and inside MuJoCo's shared library
  std::string error;
  auto kin = testing::Arm(&error);
  ASSERT_TRUE(kin) << error;
  mjData* d = nullptr;
  EXPECT_GT(Allocations([&] { d = mj_makeData(kin->m()); }), 0);
  mj_deleteData(d);
}

TEST(Allocation, PerCycleKinematicsAndIkAllocateNothing) {
  std::string error;
  auto kin = testing::Hrp1s(&error);
  ASSERT_TRUE(kin) << error;
  const int nv = kin->nv(), left = kin->left_sole(), right = kin->right_sole();
  const int imu = kin->SiteId("imu"), wrist = kin->BodyId("LARM_WRIST_R");
  std::vector<double> q(kin->njoint(), 0.0), dq(kin->njoint(), 0.1);
  q[kin->JointId("LLEG_KNEE")] = q[kin->JointId("RLEG_KNEE")] = 0.7;
  q[kin->JointId("LLEG_HIP_P")] = q[kin->JointId("RLEG_HIP_P")] = -0.35;
  q[kin->JointId("LLEG_ANKLE_P")] = q[kin->JointId("RLEG_ANKLE_P")] = -0.35;
  // everything sized before the loop, including a Jacobian written into a block
  Eigen::MatrixXd J(6, nv), J_com(3, nv), M(nv, nv), J_big(12, nv);
  Eigen::VectorXd tau(nv);
  LimbIk ik_left = LimbIk::ForSole(*kin, kin->robot().base_body, left);
  LimbIk ik_right = LimbIk::ForSole(*kin, kin->robot().base_body, right);
  const Eigen::Quaterniond quat(Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 2, 3).normalized()));
  kin->SetBasePose({0.1, 0.0, 0.68}, quat);
  kin->SetJointPositions(q.data());
  kin->Update();
  const Eigen::Vector3d p_target = kin->p_WSole(left) + Eigen::Vector3d(0.03, 0.02, 0.05);
  const Eigen::Matrix3d R_target = kin->R_WSole(left) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).matrix();

  double sink = 0;
  IkResult r_left, r_right;
  const long n = Allocations([&] {
    for (int cycle = 0; cycle < 3; ++cycle) {
      kin->SetBasePose({0.1, 0.0, 0.68}, quat);
      kin->SetJointPositions(q.data());
      kin->SetBaseVelocity({0.1, 0.2, 0.3}, {0.3, -0.2, 0.1});
      kin->SetJointVelocities(dq.data());
      kin->Update();
      sink += kin->p_WSole(left).x() + kin->R_WSole(right)(0, 0) + kin->p_WCoM().z() +
              kin->v_WCoM().x() + kin->p_WSite(imu).y() + kin->R_WBody(wrist)(1, 1);
      kin->J_WSole(left, J);
      kin->J_WSite(imu, J_big.topRows(6));
      kin->J_WBodyPoint(wrist, kin->p_WBody(wrist), J_big.bottomRows(6));
      kin->J_WCoM(J_com);
      kin->MassMatrix(M);
      kin->GravityTorques(tau);
      r_left = ik_left.Solve(*kin, p_target, R_target, q.data());
      r_right = ik_right.Solve(*kin, kin->p_WSole(right) + Eigen::Vector3d(0, 0, 2.0),
                               kin->R_WSole(right), q.data());  // unreachable
    }
  });
  EXPECT_EQ(n, 0) << "heap allocations in the per-cycle calls";
  EXPECT_EQ(r_left.status, IkStatus::kConverged) << IkStatusName(r_left.status);
  EXPECT_EQ(r_right.status, IkStatus::kUnreachable) << IkStatusName(r_right.status);
  EXPECT_TRUE(std::isfinite(sink));
}

// a chain of fewer than 6 joints (the planar arm's 2) asked for an orientation it cannot take:
// the solve that judges the least-squares best (ik.h) allocates nothing either
TEST(Allocation, ShortChainIkAllocatesNothing) {
  std::string error;
  auto kin = testing::Arm(&error);
  ASSERT_TRUE(kin) << error;
  LimbIk ik(*kin, 0, kin->BodyId("link2"), Eigen::Vector3d(testing::kL2, 0, 0));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).matrix();  // out of reach
  double q[2] = {0.4, 0.5};
  IkResult r;
  const long n = Allocations([&] {
    for (int cycle = 0; cycle < 3; ++cycle) {
      q[0] = 0.4;
      q[1] = 0.5;
      r = ik.Solve(*kin, Eigen::Vector3d(1.2, 0.5, 0), R, q);
    }
  });
  EXPECT_EQ(n, 0) << "heap allocations in a short chain's solve";
  EXPECT_EQ(r.status, IkStatus::kConverged) << IkStatusName(r.status);
  EXPECT_LT(r.position_error, 1e-5);
  EXPECT_GE(r.orientation_error, 0.3 - 1e-6);  // the roll about x is beyond both joints
}

TEST(Allocation, EstimatorUpdateAllocatesNothing) {
  // HRP-1S standing in half-sitting as its sensors would show it: torso upright (the IMU reads
  // +g along its z), each sole carrying half the weight along its sensor's z, joints moving
  std::string error;
  auto kin = testing::Hrp1s(&error);
  ASSERT_TRUE(kin) << error;
  BaseEstimator est(kin.get());
  shm::SensorBlock s{};
  for (const char* leg : {"LLEG", "RLEG"}) {
    s.q[kin->JointId(std::string(leg) + "_HIP_P")] = -0.35;
    s.q[kin->JointId(std::string(leg) + "_KNEE")] = 0.7;
    s.q[kin->JointId(std::string(leg) + "_ANKLE_P")] = -0.35;
  }
  for (int j = 0; j < kin->njoint(); ++j) s.dq[j] = 0.01;
  s.imu[0].accel[2] = 9.81;
  s.imu[0].gyro[1] = 0.01;
  for (int sole : {kin->left_sole(), kin->right_sole()})
    s.force[kin->soles()[sole].force_sensor].force[2] = 0.5 * kin->mass() * 9.81;
  ASSERT_TRUE(est.Reset(s));
  bool ok = true;
  const long n = Allocations([&] {
    for (int cycle = 0; cycle < 3; ++cycle) ok = est.Update(s, 0.005) && ok;
  });
  EXPECT_EQ(n, 0) << "heap allocations in BaseEstimator::Update";
  EXPECT_TRUE(ok);
  EXPECT_TRUE(est.estimate().contact[0] && est.estimate().contact[1]);
}

#elif defined(OHRP_SANITIZE)
TEST(Allocation, NotUnderSanitizers) {
  GTEST_SKIP() << "AddressSanitizer replaces malloc itself: the counting replacement is left out of "
                  "the sanitizer build (the normal build runs it)";
}
#else
TEST(Allocation, NeedsGlibc) { GTEST_SKIP() << "malloc is replaced through glibc's __libc_ entry points"; }
#endif

}  // namespace
}  // namespace ohrp::model
