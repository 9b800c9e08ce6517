// The guard on a leg with a foot: braked while its foot carries no load, never while loaded,
// the load's hysteresis (docs/selfcollision.md, "A leg whose foot is in the air"). The
// fixture: self_collision_guard_fixture.h.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "self_collision_guard_fixture.h"

namespace ohrp::controllers::guard_testing {
namespace {

TEST_F(LegGuardTest, BrakesALegWhoseFootIsInTheAir) {
  Feet(5.0);  // the sole's own weight: in the air
  SelfCollisionGuard g;
  ASSERT_TRUE(Swing(&g));
  EXPECT_FALSE(g.loaded(kRlegHipR));
  EXPECT_TRUE(g.holding());
  EXPECT_EQ(g.holds(), 1u);
  EXPECT_GE(g.leg_brake_cycles(), 1);
  const double v1 = commands_.joint[kRlegHipR].dq_ref;
  EXPECT_GT(v1, 0.0);
  EXPECT_LT(v1, 3.0);
  EXPECT_NEAR(commands_.joint[kRlegHipR].q_ref, 0.5 * (3.0 + v1) * 0.005, 1e-12);
  // the unloaded leg's rate: over the free links' inertia (inertia_free), the limit less the
  // load: none measured (torque 0, no acceleration), the slack (gravity bound times the angle
  // the fastest joint turns in three periods, the damping's torque)
  const collision::JointDynamics& d = file_.dynamics[kRlegHipR];
  const double load = d.gravity_max * std::min(1.0, 3 * 3.0 * 0.005) + d.damping * 3.0;
  EXPECT_NEAR((3.0 - v1) / 0.005, (200 - std::min(d.gravity_max, load)) / d.inertia_free, 1e-6);
}

TEST_F(LegGuardTest, NeverBrakesALoadedLeg) {
  Feet(5 * on_);  // standing: half the weight on each foot
  SelfCollisionGuard g;
  EXPECT_FALSE(Swing(&g));
  EXPECT_TRUE(g.loaded(kRlegHipR));
  EXPECT_EQ(g.holds(), 0u);
  EXPECT_EQ(commands_.joint[kRlegHipR].q_ref, 0.0);  // the command kept
  EXPECT_EQ(g.leg_brake_cycles(), 0);
}

// standing on the other foot, a leg in the air is not braked: its motion may be a step the
// guard cannot see (braking it mid-step drops the robot)
TEST_F(LegGuardTest, NotBrakedWhileTheOtherFootCarriesTheRobot) {
  sensors_.force[1].force[2] = 10 * on_;  // the left foot carries the whole weight
  SelfCollisionGuard g;
  EXPECT_FALSE(Swing(&g));
  EXPECT_FALSE(g.loaded(kRlegHipR));
  EXPECT_TRUE(g.loaded(kLlegHipR));
  EXPECT_EQ(commands_.joint[kRlegHipR].q_ref, 0.0);
  EXPECT_EQ(g.leg_brake_cycles(), 0);
}

// a controller whose balance moves the legs (balance, walk: guard_may_brake_legs false): a leg
// in the air is not braked either
TEST_F(LegGuardTest, NotBrakedWhenTheControllerBalancesOnTheLegs) {
  Feet(5.0);
  SelfCollisionGuard g;
  g.set_brake_unloaded_legs(false);
  EXPECT_FALSE(Swing(&g));
  EXPECT_FALSE(g.loaded(kRlegHipR));  // measured in the air all the same
  EXPECT_EQ(commands_.joint[kRlegHipR].q_ref, 0.0);
  EXPECT_EQ(g.leg_brake_cycles(), 0);
}

TEST_F(LegGuardTest, TheLoadHasHysteresis) {
  SelfCollisionGuard g;
  ASSERT_EQ(g.Configure(kFile, header_), "");
  double q[shm::kMaxJoints] = {};
  Command(q, header_.njoint, &commands_);
  const auto cycle = [&](double fz) {
    Feet(fz);
    shm::CommandBlock c = commands_;
    g.Filter(sensors_, &c);
    return g.loaded(kRlegHipR);
  };
  Feet(0.75 * on_);  // within the band at activation: loaded (the conservative side)
  g.Activate(sensors_);
  EXPECT_TRUE(g.loaded(kRlegHipR));
  EXPECT_FALSE(g.loaded(6));  // an arm has no foot
  EXPECT_TRUE(cycle(0.75 * on_));
  EXPECT_TRUE(cycle(0.51 * on_));   // above half: still loaded
  EXPECT_FALSE(cycle(0.49 * on_));  // below half: unloaded
  EXPECT_FALSE(cycle(0.99 * on_));  // below support_force: still unloaded
  EXPECT_TRUE(cycle(1.01 * on_));   // above: loaded
  EXPECT_TRUE(cycle(NAN));          // no finite reading: loaded
  EXPECT_FALSE(cycle(0.0));
  // a leg whose sensor the segment lacks is always loaded (never braked)
  SelfCollisionGuard h;
  header_.nforce = 1;  // the right foot's sensor only
  ASSERT_EQ(h.Configure(kFile, header_), "");
  Feet(0.0);
  h.Activate(sensors_);
  EXPECT_FALSE(h.loaded(kRlegHipR));
  EXPECT_TRUE(h.loaded(kLlegHipR));
}

}  // namespace
}  // namespace ohrp::controllers::guard_testing
