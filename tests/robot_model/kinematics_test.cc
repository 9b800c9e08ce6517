// Tests robot_model/kinematics: forward kinematics, Jacobians, the centre of mass, the mass
// matrix and gravity torques against closed forms (a planar two-link arm) and against finite
// differences and energy identities (the floating HRP-1S).
#include "robot_model/kinematics.h"

#include "random_state.h"
#include "test_models.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>

namespace ohrp::model {
namespace {

using namespace testing;  // NOLINT: the test models

std::unique_ptr<Kinematics> Arm() {
  std::string error;
  auto kin = testing::Arm(&error);
  EXPECT_TRUE(kin) << error;
  return kin;
}

std::unique_ptr<Kinematics> Hrp1s() {
  std::string error;
  auto kin = testing::Hrp1s(&error);
  EXPECT_TRUE(kin) << error;
  return kin;
}

// rotation vector of R
Eigen::Vector3d Log(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

const double kAngles[][2] = {{0, 0}, {0.3, -0.7}, {1.2, 2.1}, {-2.5, 0.4}, {3.0, -3.0}};

//---------------- the planar arm against closed forms ----------------

TEST(KinematicsArm, TipPositionAndJacobianMatchTheTextbook) {
  auto kin = Arm();
  ASSERT_TRUE(kin);
  ASSERT_FALSE(kin->floating());
  ASSERT_EQ(kin->nv(), 2);
  const int tip = kin->SiteId("tip");
  Eigen::MatrixXd J(6, 2);
  for (const auto& a : kAngles) {
    kin->SetJointPositions(a);
    kin->Update();
    const double c1 = std::cos(a[0]), s1 = std::sin(a[0]);
    const double c12 = std::cos(a[0] + a[1]), s12 = std::sin(a[0] + a[1]);
    const Eigen::Vector3d p(kL1 * c1 + kL2 * c12, kL1 * s1 + kL2 * s12, 0);
    EXPECT_LT((kin->p_WSite(tip) - p).norm(), 1e-12);
    const Eigen::Matrix3d R = Eigen::AngleAxisd(a[0] + a[1], Eigen::Vector3d::UnitZ()).matrix();
    EXPECT_LT((kin->R_WSite(tip) - R).norm(), 1e-12);
    kin->J_WSite(tip, J);
    Eigen::MatrixXd J_ref = Eigen::MatrixXd::Zero(6, 2);
    J_ref << -kL1 * s1 - kL2 * s12, -kL2 * s12,
              kL1 * c1 + kL2 * c12,  kL2 * c12,
              0, 0,
              0, 0,
              0, 0,
              1, 1;
    EXPECT_LT((J - J_ref).norm(), 1e-12) << "q = " << a[0] << ", " << a[1] << "\n" << J;
  }
}

TEST(KinematicsArm, CentreOfMassAndItsJacobianMatchTheClosedForm) {
  auto kin = Arm();
  ASSERT_TRUE(kin);
  EXPECT_DOUBLE_EQ(kin->mass(), kM1 + kM2);
  Eigen::MatrixXd J(3, 2);
  for (const auto& a : kAngles) {
    kin->SetJointPositions(a);
    const double dq[2] = {0.7, -1.3};
    kin->SetJointVelocities(dq);
    kin->Update();
    const double c1 = std::cos(a[0]), s1 = std::sin(a[0]);
    const double c12 = std::cos(a[0] + a[1]), s12 = std::sin(a[0] + a[1]);
    const double M = kM1 + kM2;
    const Eigen::Vector3d p((kM1 * kLc1 * c1 + kM2 * (kL1 * c1 + kLc2 * c12)) / M,
                            (kM1 * kLc1 * s1 + kM2 * (kL1 * s1 + kLc2 * s12)) / M, 0);
    EXPECT_LT((kin->p_WCoM() - p).norm(), 1e-12);
    Eigen::MatrixXd J_ref(3, 2);
    J_ref << -(kM1 * kLc1 * s1 + kM2 * (kL1 * s1 + kLc2 * s12)) / M, -kM2 * kLc2 * s12 / M,
              (kM1 * kLc1 * c1 + kM2 * (kL1 * c1 + kLc2 * c12)) / M,  kM2 * kLc2 * c12 / M,
              0, 0;
    kin->J_WCoM(J);
    EXPECT_LT((J - J_ref).norm(), 1e-12);
    EXPECT_LT((kin->v_WCoM() - J_ref * Eigen::Vector2d(dq[0], dq[1])).norm(), 1e-12);
  }
}

TEST(KinematicsArm, MassMatrixMatchesTheClosedFormWithArmature) {
  auto kin = Arm();
  ASSERT_TRUE(kin);
  Eigen::MatrixXd M(2, 2);
  for (const auto& a : kAngles) {
    kin->SetJointPositions(a);
    kin->Update();
    kin->MassMatrix(M);
    const double c2 = std::cos(a[1]);
    const double m11 = kI1 + kM1 * kLc1 * kLc1 + kI2 +
                       kM2 * (kL1 * kL1 + kLc2 * kLc2 + 2 * kL1 * kLc2 * c2) + kA1;
    const double m12 = kI2 + kM2 * (kLc2 * kLc2 + kL1 * kLc2 * c2);
    const double m22 = kI2 + kM2 * kLc2 * kLc2 + kA2;
    EXPECT_NEAR(M(0, 0), m11, 1e-12);
    EXPECT_NEAR(M(0, 1), m12, 1e-12);
    EXPECT_NEAR(M(1, 0), m12, 1e-12);
    EXPECT_NEAR(M(1, 1), m22, 1e-12);
  }
}

TEST(KinematicsArm, GravityTorquesMatchTheClosedFormWhateverTheVelocity) {
  auto kin = Arm();
  ASSERT_TRUE(kin);
  Eigen::VectorXd tau(2);
  for (const auto& a : kAngles) {
    kin->SetJointPositions(a);
    const double dq[2] = {2.0, -3.0};  // must not leak into the gravity torques
    kin->SetJointVelocities(dq);
    kin->Update();
    kin->GravityTorques(tau);
    // the torque that holds the arm: dV/dq with V = m g y of each link
    const double c1 = std::cos(a[0]), c12 = std::cos(a[0] + a[1]);
    EXPECT_NEAR(tau[0], (kM1 * kLc1 + kM2 * kL1) * kG * c1 + kM2 * kLc2 * kG * c12, 1e-10);
    EXPECT_NEAR(tau[1], kM2 * kLc2 * kG * c12, 1e-10);
  }
}

TEST(KinematicsArm, ChainAndNames) {
  auto kin = Arm();
  ASSERT_TRUE(kin);
  const int link1 = kin->BodyId("link1"), link2 = kin->BodyId("link2");
  EXPECT_EQ(kin->Chain(0, link2), (std::vector<int>{0, 1}));
  EXPECT_EQ(kin->Chain(link1, link2), (std::vector<int>{1}));
  EXPECT_TRUE(kin->Chain(link2, link1).empty());
  EXPECT_EQ(kin->JointId("j2"), 1);
  EXPECT_EQ(kin->JointId("nope"), -1);
  EXPECT_EQ(kin->left_sole(), -1);
}

TEST(KinematicsArm, PassiveJointStaysAtItsReferenceAndHasNoColumn) {
  // the arm with a passive hinge (no motor) at the elbow, reference angle 0.5 rad
  std::string xml = kArm;
  const std::string link2 = R"(<body name="link2" pos="1 0 0">)";
  xml.replace(xml.find(link2), link2.size(),
              R"(<body name="elbow" pos="1 0 0"><joint name="passive" type="hinge" axis="0 0 1" ref="0.5"/>
                 <inertial pos="0 0 0" mass="0.1" diaginertia="0.001 0.001 0.001"/>
                 <body name="link2">)");
  xml.replace(xml.find("</body>"), 0, "</body>");
  std::string error;
  mjModel* m = LoadString(xml.c_str(), &error);
  ASSERT_TRUE(m) << error;
  auto kin = Kinematics::FromModel(m, &error);
  mj_deleteModel(m);
  ASSERT_TRUE(kin) << error;
  ASSERT_EQ(kin->nv(), 2);
  EXPECT_EQ(kin->Chain(0, kin->BodyId("link2")), (std::vector<int>{0, 1}));
  const double q[2] = {0.3, -0.9};
  kin->SetJointPositions(q);
  kin->Update();
  // the passive joint at qpos0 = ref, i.e. the pose as written (MuJoCo turns a hinge by
  // qpos - ref): the two-link closed form; at qpos = 0 the elbow would be turned by -0.5
  const double a1 = q[0], a12 = q[0] + q[1];
  const Eigen::Vector3d p(kL1 * std::cos(a1) + kL2 * std::cos(a12), kL1 * std::sin(a1) + kL2 * std::sin(a12), 0);
  EXPECT_LT((kin->p_WSite(kin->SiteId("tip")) - p).norm(), 1e-12);
  Eigen::MatrixXd J(6, 2);
  kin->J_WSite(kin->SiteId("tip"), J);
  EXPECT_NEAR(J(0, 1), -kL2 * std::sin(a12), 1e-12);
  EXPECT_NEAR(J(1, 0), kL1 * std::cos(a1) + kL2 * std::cos(a12), 1e-12);
}

//---------------- the floating HRP-1S against finite differences ----------------

// central differences of a frame pose (position, orientation) along every column
Eigen::MatrixXd NumericJacobian(Kinematics& kin, const State& s,
                                const std::function<void(Eigen::Vector3d*, Eigen::Matrix3d*)>& frame) {
  constexpr double h = 1e-6;
  Eigen::MatrixXd J(6, kin.nv());
  for (int c = 0; c < kin.nv(); ++c) {
    Eigen::Vector3d p_plus, p_minus;
    Eigen::Matrix3d R_plus, R_minus;
    Apply(kin, Perturb(s, c, h));
    frame(&p_plus, &R_plus);
    Apply(kin, Perturb(s, c, -h));
    frame(&p_minus, &R_minus);
    J.block<3, 1>(0, c) = (p_plus - p_minus) / (2 * h);
    J.block<3, 1>(3, c) = Log(R_plus * R_minus.transpose()) / (2 * h);
  }
  Apply(kin, s);
  return J;
}

TEST(KinematicsHrp1s, FrameJacobiansMatchFiniteDifferences) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  ASSERT_TRUE(kin->floating());
  ASSERT_EQ(kin->nv(), 6 + 29);
  std::mt19937 rng(7);
  const int left = kin->left_sole(), imu = kin->SiteId("imu"), hand = kin->SiteId("rhsensor");
  const int wrist = kin->BodyId("LARM_WRIST_R");
  const Eigen::Vector3d offset(0.05, -0.02, -0.1);  // a point on the wrist body, in its frame
  Eigen::MatrixXd J(6, kin->nv());
  for (int trial = 0; trial < 3; ++trial) {
    const State s = RandomState(*kin, &rng);
    // the left sole's frame S
    Apply(*kin, s);
    kin->J_WSole(left, J);
    Eigen::MatrixXd Jn = NumericJacobian(*kin, s, [&](Eigen::Vector3d* p, Eigen::Matrix3d* R) {
      *p = kin->p_WSole(left);
      *R = kin->R_WSole(left);
    });
    EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-6) << "sole\n" << (J - Jn);
    // two sites
    for (int site : {imu, hand}) {
      kin->J_WSite(site, J);
      Jn = NumericJacobian(*kin, s, [&](Eigen::Vector3d* p, Eigen::Matrix3d* R) {
        *p = kin->p_WSite(site);
        *R = kin->R_WSite(site);
      });
      EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-6) << "site " << site;
    }
    // a point fixed on a body
    kin->J_WBodyPoint(wrist, kin->p_WBody(wrist) + kin->R_WBody(wrist) * offset, J);
    Jn = NumericJacobian(*kin, s, [&](Eigen::Vector3d* p, Eigen::Matrix3d* R) {
      *p = kin->p_WBody(wrist) + kin->R_WBody(wrist) * offset;
      *R = kin->R_WBody(wrist);
    });
    EXPECT_LT((J - Jn).cwiseAbs().maxCoeff(), 1e-6) << "body point";
  }
}

TEST(KinematicsHrp1s, CentreOfMassJacobianAndVelocityMatchFiniteDifferences) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd J(3, kin->nv());
  for (int trial = 0; trial < 3; ++trial) {
    const State s = RandomState(*kin, &rng);
    Apply(*kin, s);
    kin->J_WCoM(J);
    Eigen::MatrixXd Jn = NumericJacobian(*kin, s, [&](Eigen::Vector3d* p, Eigen::Matrix3d* R) {
      *p = kin->p_WCoM();
      *R = Eigen::Matrix3d::Identity();
    });
    EXPECT_LT((J - Jn.topRows<3>()).cwiseAbs().maxCoeff(), 1e-6);

    // v_WCoM from a random velocity: J_WCoM v, and the derivative of p_WCoM along v
    Eigen::VectorXd v(kin->nv());
    for (int c = 0; c < kin->nv(); ++c) v[c] = u(rng);
    kin->SetBaseVelocity(v.head<3>(), v.segment<3>(3));
    kin->SetJointVelocities(v.data() + 6);
    kin->Update();
    EXPECT_LT((kin->v_WCoM() - J * v).norm(), 1e-12);
    Eigen::VectorXd tau(kin->nv());
    kin->GravityTorques(tau);  // zeroes MuJoCo's body velocities: v_WCoM must not change
    EXPECT_LT((kin->v_WCoM() - J * v).norm(), 1e-12);
    constexpr double h = 1e-6;
    State plus = s, minus = s;
    plus.p_WB += h * v.head<3>();
    minus.p_WB -= h * v.head<3>();
    const Eigen::Vector3d w = v.segment<3>(3);
    plus.quat_WB = Eigen::Quaterniond(Eigen::AngleAxisd(h * w.norm(), w.normalized())) * s.quat_WB;
    minus.quat_WB = Eigen::Quaterniond(Eigen::AngleAxisd(-h * w.norm(), w.normalized())) * s.quat_WB;
    for (int j = 0; j < kin->njoint(); ++j) {
      plus.q[j] += h * v[6 + j];
      minus.q[j] -= h * v[6 + j];
    }
    const Eigen::Vector3d v_WCoM = kin->v_WCoM();
    Apply(*kin, plus);
    const Eigen::Vector3d p_plus = kin->p_WCoM();
    Apply(*kin, minus);
    const Eigen::Vector3d p_minus = kin->p_WCoM();
    EXPECT_LT((v_WCoM - (p_plus - p_minus) / (2 * h)).norm(), 1e-6);
  }
}

TEST(KinematicsHrp1s, MassMatrixGivesTheKineticEnergyOfTheBodies) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  const mjModel* m = kin->m();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const int nv = kin->nv();
  Eigen::MatrixXd M(nv, nv), J(6, nv);
  for (int trial = 0; trial < 3; ++trial) {
    Apply(*kin, RandomState(*kin, &rng));
    kin->MassMatrix(M);
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12);
    // the base's translational block is the total mass
    EXPECT_LT((M.topLeftCorner<3, 3>() - kin->mass() * Eigen::Matrix3d::Identity()).norm(), 1e-9);
    Eigen::VectorXd v(nv);
    for (int c = 0; c < nv; ++c) v[c] = u(rng);
    // the kinetic energy body by body (velocity of the centre of mass, angular velocity and
    // the inertia turned into W), plus the rotors' armature
    double energy = 0;
    for (int b = 1; b < m->nbody; ++b) {
      const Eigen::Vector3d p_com = kin->p_WBody(b) + kin->R_WBody(b) * Eigen::Vector3d(m->body_ipos + 3 * b);
      kin->J_WBodyPoint(b, p_com, J);
      const Eigen::Vector3d vel = J.topRows<3>() * v, w = J.bottomRows<3>() * v;
      const Eigen::Quaterniond iquat(m->body_iquat[4 * b], m->body_iquat[4 * b + 1],
                                     m->body_iquat[4 * b + 2], m->body_iquat[4 * b + 3]);
      const Eigen::Matrix3d R = kin->R_WBody(b) * iquat.toRotationMatrix();
      const Eigen::Matrix3d I = R * Eigen::Vector3d(m->body_inertia + 3 * b).asDiagonal() * R.transpose();
      energy += 0.5 * m->body_mass[b] * vel.squaredNorm() + 0.5 * w.dot(I * w);
    }
    for (int j = 0; j < kin->njoint(); ++j) {
      energy += 0.5 * m->dof_armature[kin->robot().joints[j].dof_adr] * v[6 + j] * v[6 + j];
    }
    EXPECT_NEAR(0.5 * v.dot(M * v), energy, 1e-10 * energy);
  }
}

TEST(KinematicsHrp1s, GravityTorquesAreTheWeightThroughTheCentreOfMassJacobian) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  std::mt19937 rng(5);
  const int nv = kin->nv();
  Eigen::VectorXd tau(nv);
  Eigen::MatrixXd J(3, nv);
  const double weight = kin->mass() * 9.81;  // [N] (the model's gravity is -9.81 z)
  ASSERT_NEAR(kin->m()->opt.gravity[2], -9.81, 1e-12);
  for (int trial = 0; trial < 3; ++trial) {
    const State s = RandomState(*kin, &rng);
    Apply(*kin, s);
    kin->GravityTorques(tau);
    kin->J_WCoM(J);
    // dV/dq with V = m g z_CoM
    const Eigen::VectorXd ref = weight * J.row(2).transpose();
    EXPECT_LT((tau - ref).cwiseAbs().maxCoeff(), 1e-9 * weight);
    // base part: the weight, and its moment about the base origin (w in W)
    EXPECT_LT((tau.head<3>() - Eigen::Vector3d(0, 0, weight)).norm(), 1e-9 * weight);
    const Eigen::Vector3d moment = (kin->p_WCoM() - s.p_WB).cross(Eigen::Vector3d(0, 0, weight));
    EXPECT_LT((tau.segment<3>(3) - moment).norm(), 1e-9 * weight);
  }
}

TEST(KinematicsHrp1s, SolesAtHalfSittingMatchMujocoAndTheLegGeometry) {
  auto kin = Hrp1s();
  ASSERT_TRUE(kin);
  const mjModel* m = kin->m();
  ASSERT_EQ(kin->soles().size(), 2u);
  const int left = kin->left_sole(), right = kin->right_sole();
  ASSERT_GE(left, 0);
  EXPECT_EQ(kin->soles()[left].name, "LLEG_SOLE");
  EXPECT_EQ(kin->soles()[right].name, "RLEG_SOLE");
  EXPECT_EQ(kin->robot().forces[kin->soles()[left].force_sensor].name, "lfsensor");
  EXPECT_EQ(kin->robot().forces[kin->soles()[right].force_sensor].name, "rfsensor");
  EXPECT_EQ(kin->SoleIndex("LLEG_SOLE"), left);

  // the keyframe in our API, and the same in a MuJoCo simulation
  const int key = mj_name2id(m, mjOBJ_KEY, "halfsit");
  ASSERT_GE(key, 0);
  const mjtNum* qpos = m->key_qpos + key * m->nq;
  std::vector<double> q;
  for (const JointMap& j : kin->robot().joints) q.push_back(qpos[j.qpos_adr]);
  const int b = kin->robot().base_qpos;
  kin->SetBasePose({qpos[b], qpos[b + 1], qpos[b + 2]},
                   Eigen::Quaterniond(qpos[b + 3], qpos[b + 4], qpos[b + 5], qpos[b + 6]));
  kin->SetJointPositions(q.data());
  kin->Update();
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, key);
  mj_forward(m, d);
  for (int s : {left, right}) {
    const int g = kin->soles()[s].geom_id;
    const Eigen::Matrix3d R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d->geom_xmat + 9 * g);
    const Eigen::Vector3d p = Eigen::Vector3d(d->geom_xpos + 3 * g) - 0.01 * R.col(2);
    EXPECT_LT((kin->p_WSole(s) - p).norm(), 1e-12);
    EXPECT_LT((kin->R_WSole(s) - R).norm(), 1e-12);
  }
  mj_deleteData(d);

  // closed form: hip pitch -a, knee 2a, ankle -a keep the sole flat under the hip; thigh
  // 0.3535 m, shin 0.3 m, sole 0.055 m ahead of and 0.07 m below the ankle
  const double a = 0.35, thigh = 0.3535, shin = 0.3;
  ASSERT_NEAR(kin->q(kin->JointId("LLEG_KNEE")), 2 * a, 1e-12);
  ASSERT_NEAR(kin->q(kin->JointId("RLEG_HIP_P")), -a, 1e-12);
  for (int s : {left, right}) {
    const double y = s == left ? 0.09 : -0.09;
    const Eigen::Vector3d p((thigh - shin) * std::sin(a) + 0.055, y,
                            qpos[b + 2] - (thigh + shin) * std::cos(a) - 0.07);
    EXPECT_LT((kin->p_WSole(s) - p).norm(), 1e-9) << kin->p_WSole(s).transpose();
    EXPECT_LT((kin->R_WSole(s) - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  }
  // the standing keyframe puts the soles on the floor
  EXPECT_NEAR(kin->p_WSole(left).z(), 0.0, 1e-6);
}

}  // namespace
}  // namespace ohrp::model
