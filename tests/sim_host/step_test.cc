// sim_host's physics step (sim_host/step.h): the robot standing on its implicit soft soles steps
// without a heap allocation, the split step is mj_step's, skipping the sensors on a cycle's
// early steps changes nothing published, and the step reports when each push starts and ends.
#include "sim_host/step.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../robot_model/count_allocations.h"
#include "leaning_robot.h"

namespace ohrp::sim {
namespace {

TEST(PhysicsStep, StandingOnTheImplicitSoftSolesAllocatesNothing) {
  testing::LeaningRobot r;
  r.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.002, 0.0, 1.0);
  ASSERT_TRUE(r.soft().implicit());
  // settle onto both soles (the implicit correction is then computed at every step)
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(r.Step());
  ASSERT_TRUE(r.soft().wrenches()[0].in_contact && r.soft().wrenches()[1].in_contact);
#ifdef OHRP_CAN_COUNT
  EXPECT_EQ(ohrp::testing::Allocations([&] {
              for (int i = 0; i < 100; ++i) r.Step();
            }),
            0);
#endif
  // and it stands: the soles carry the robot
  double fz = 0;
  for (const auto& w : r.soft().wrenches()) fz += w.force.z();
  EXPECT_NEAR(fz, r.robot().total_mass * 9.81, 0.05 * r.robot().total_mass * 9.81);
}

// The step splits mj_step around the contact (mj_step1, contact, mj_step2) so that the contact
// uses MuJoCo's kinematics and mass matrix of the step: the robot must move exactly as with
// mj_step in one piece after the contact computed them itself, for Euler and for the implicit
// integrator (whose joint damping mj_step2 must integrate as mj_step does), while it leans and
// its soles load and unload.
TEST(PhysicsStep, SplitStepIsTheUnsplitOne) {
  for (int integrator : {mjINT_EULER, mjINT_IMPLICIT}) {
    testing::LeaningRobot split, whole;
    split.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.3, 1.0);
    whole.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.3, 1.0);
    split.m()->opt.integrator = whole.m()->opt.integrator = integrator;
    for (int i = 0; i < 1500; ++i) {
      ASSERT_TRUE(split.Step());
      ASSERT_TRUE(whole.Step(/*unsplit=*/true));
    }
    double worst = 0;
    for (int i = 0; i < split.m()->nq; ++i)
      worst = std::max(worst, std::abs(split.d()->qpos[i] - whole.d()->qpos[i]));
    for (int i = 0; i < split.m()->nv; ++i)
      worst = std::max(worst, 1e-3 * std::abs(split.d()->qvel[i] - whole.d()->qvel[i]));
    EXPECT_LT(worst, 1e-12) << "integrator " << integrator;
    // and the robot did move: the lean tilted it
    EXPECT_GT(std::abs(split.d()->qpos[3] - 1), 1e-4);
  }
}

// sim_host computes MuJoCo's sensors only on a control cycle's last step: the motion must be
// bit for bit that of computing them at every step, and the sensors after each cycle's last
// step the same values; in between they are left as they were (so the skip did happen)
TEST(PhysicsStep, SensorsSkippedBeforeTheCyclesLastStepChangeNothingPublished) {
  testing::LeaningRobot every, last;
  every.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.3, 1.0);
  last.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.3, 1.0);
  ASSERT_GT(every.m()->nsensordata, 0);
  const int kSteps = 5;  // per control cycle
  long stale = 0;
  for (int i = 0; i < 1500; ++i) {
    const bool published = i % kSteps == kSteps - 1;
    ASSERT_TRUE(every.Step());
    ASSERT_TRUE(last.Step(false, published));
    for (int k = 0; k < every.m()->nq; ++k) ASSERT_EQ(every.d()->qpos[k], last.d()->qpos[k]) << i;
    for (int k = 0; k < every.m()->nv; ++k) ASSERT_EQ(every.d()->qvel[k], last.d()->qvel[k]) << i;
    for (int k = 0; k < every.m()->nsensordata; ++k) {
      if (published) ASSERT_EQ(every.d()->sensordata[k], last.d()->sensordata[k]) << i << " " << k;
      else stale += every.d()->sensordata[k] != last.d()->sensordata[k];
    }
  }
  EXPECT_GT(stale, 1000);
  EXPECT_EQ(last.m()->opt.disableflags & mjDSBL_SENSOR, 0);  // the flag is the step's only
}

// The implicit soles' apparent inverse inertia (half solves over the sole bodies' dof chains,
// A = X X^T) is J M^-1 J^T from MuJoCo's full solve, both soles of the leaning robot together
// (coupled)
TEST(PhysicsStep, SolesMobilityIsJMinvJt) {
  testing::LeaningRobot r;
  r.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.3, 1.0);
  for (int i = 0; i < 300; ++i) ASSERT_TRUE(r.Step());
  const mjModel* m = r.m();
  mjData* d = r.d();
  const std::vector<int>& bodies = r.soft().sole_bodies();
  ASSERT_EQ(bodies.size(), 2u);
  const int n = 6 * static_cast<int>(bodies.size()), nv = m->nv;
  mj_step1(m, d);  // the contact's own kinematics and factorised M at this state
  r.soft().ApplyAfterStep1(m, d);
  std::vector<double> J(static_cast<size_t>(n) * nv), MinvJt(J.size());
  for (size_t k = 0; k < bodies.size(); ++k)
    mj_jacBodyCom(m, d, J.data() + 6 * k * nv, J.data() + (6 * k + 3) * nv, bodies[k]);
  mj_solveM(m, d, MinvJt.data(), J.data(), n);
  const Eigen::MatrixXd& A = r.soft().mobility();
  ASSERT_EQ(A.rows(), n);
  double worst = 0, scale = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double a = 0;
      for (int k = 0; k < nv; ++k) a += J[i * nv + k] * MinvJt[j * nv + k];
      worst = std::max(worst, std::abs(A(i, j) - a));
      scale = std::max(scale, std::abs(a));
    }
  EXPECT_LT(worst, 1e-12 * scale) << "largest entry " << scale;
  EXPECT_GT(std::abs(A(0, 6)) + std::abs(A(2, 8)), 1e-6 * scale);  // the soles are coupled
}

TEST(PhysicsStep, ReportsEachPushStartAndEnd) {
  testing::LeaningRobot r;
  r.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0.001, 0.0, 1.0);
  Perturbation push;
  push.t0 = 0.010;
  push.t1 = 0.020;
  push.force[0] = 50;
  const std::vector<Perturbation> pushes{push};
  PhysicsStep step(r.m(), r.d(), {nullptr, nullptr, &pushes, r.robot().base_body, nullptr});
  std::vector<double> changes;
  for (int i = 0; i < 30; ++i) {
    const double t = r.d()->time;
    ASSERT_TRUE(step.Step());
    if (step.push_changed(0)) changes.push_back(t);
  }
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_NEAR(changes[0], 0.010, 1e-9);
  EXPECT_NEAR(changes[1], 0.020, 1e-9);
  EXPECT_EQ(step.steps(), 30u);
}

}  // namespace
}  // namespace ohrp::sim
