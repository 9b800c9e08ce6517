// sim_host's physics step (sim_host/step.h): the robot standing on its implicit soft soles steps
// without a heap allocation, and the step reports when each push starts and ends.
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
