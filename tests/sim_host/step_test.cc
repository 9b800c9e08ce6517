// sim_host's physics step (sim_host/step.h): the robot standing on its implicit soft soles steps
// without a heap allocation, and the step reports when each push starts and ends.
#include "sim_host/step.h"

#include <gtest/gtest.h>

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
