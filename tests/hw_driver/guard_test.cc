// Tests the driver's command guard: rejection of bad joint commands (velocity references beyond
// the joint speed among them; the joint holds),
// clamping into the range, the servo-on hold and the damped hold of the safe mode.
#include "hw_driver/guard.h"

#include <gtest/gtest.h>

#include <limits>

namespace ohrp::hw {
namespace {

shm::ProducerConfig TwoJoints() {
  shm::ProducerConfig c;
  c.joint_names = {"a", "b"};
  c.q_min = {-1.0, -0.5};
  c.q_max = {1.0, 0.5};
  c.tau_max = {10.0, 5.0};
  c.default_kp = {100.0, 50.0};
  c.default_kd = {2.0, 1.0};
  return c;
}

shm::CommandBlock Position(double qa, double qb) {
  shm::CommandBlock c{};
  c.njoint = 2;
  for (int i = 0; i < 2; ++i) {
    c.joint[i].mode = shm::JointMode::kPosition;
    c.joint[i].kp = 10;
    c.joint[i].kd = 1;
  }
  c.joint[0].q_ref = qa;
  c.joint[1].q_ref = qb;
  return c;
}

TEST(CommandGuard, ServoOnHoldsTheMeasuredPositionsWithDefaultGains) {
  CommandGuard g(TwoJoints());
  const double q[2] = {0.3, -0.2};
  g.HoldMeasured(q);
  EXPECT_EQ(g.references()[0].mode, shm::JointMode::kPosition);
  EXPECT_DOUBLE_EQ(g.references()[0].q_ref, 0.3);
  EXPECT_DOUBLE_EQ(g.references()[1].q_ref, -0.2);
  EXPECT_DOUBLE_EQ(g.references()[0].kp, 100.0);
  EXPECT_DOUBLE_EQ(g.references()[1].kd, 1.0);
}

TEST(CommandGuard, NanJointIsRejectedCountedAndHolds) {
  CommandGuard g(TwoJoints());
  const double q[2] = {0.0, 0.1};
  g.HoldMeasured(q);
  EXPECT_EQ(g.Accept(Position(0.5, std::numeric_limits<double>::quiet_NaN())), 1);
  EXPECT_DOUBLE_EQ(g.references()[0].q_ref, 0.5);
  EXPECT_DOUBLE_EQ(g.references()[1].q_ref, 0.1);  // held
  EXPECT_EQ(g.rejected_per_joint()[0], 0u);
  EXPECT_EQ(g.rejected_per_joint()[1], 1u);
  EXPECT_EQ(g.rejected_total(), 1u);
}

TEST(CommandGuard, OutOfRangeBadGainsAndExcessTorqueAreRejected) {
  CommandGuard g(TwoJoints());
  EXPECT_EQ(g.Accept(Position(1.5, 0.0)), 1);  // beyond the range
  auto c = Position(0.0, 0.0);
  c.joint[1].kp = -1;
  EXPECT_EQ(g.Accept(c), 1);
  c = Position(0.0, 0.0);
  c.joint[0].mode = shm::JointMode::kTorque;
  c.joint[0].tau_ff = 11;  // limit 10
  EXPECT_EQ(g.Accept(c), 1);
  c = Position(0.0, 0.0);
  c.joint[1].mode = static_cast<shm::JointMode>(42);
  EXPECT_EQ(g.Accept(c), 1);
  c.njoint = 3;  // a block for another robot: every joint
  EXPECT_EQ(g.Accept(c), 2);
}

TEST(CommandGuard, VelocityReferencesBeyondTheJointSpeedAreRejected) {
  CommandGuard g(TwoJoints());
  const double q[2] = {0.0, 0.1};
  g.HoldMeasured(q);
  auto c = Position(0.5, 0.2);
  c.joint[0].dq_ref = 1e300;
  c.joint[1].mode = shm::JointMode::kVelocity;
  c.joint[1].dq_ref = -2.0 * kMaxJointSpeed;
  EXPECT_EQ(g.Accept(c), 2);
  EXPECT_DOUBLE_EQ(g.references()[0].q_ref, 0.0);  // held
  EXPECT_DOUBLE_EQ(g.references()[0].dq_ref, 0.0);
  EXPECT_EQ(g.references()[1].mode, shm::JointMode::kPosition);
  c.joint[0].dq_ref = kMaxJointSpeed;
  c.joint[1].dq_ref = -kMaxJointSpeed;
  EXPECT_EQ(g.Accept(c), 0);
}

TEST(CommandGuard, ReferencesWithinTheToleranceAreClampedIntoTheRange) {
  CommandGuard g(TwoJoints());
  EXPECT_EQ(g.Accept(Position(1.0 + 0.5 * kRangeTolerance, -0.5 - 0.5 * kRangeTolerance)), 0);
  EXPECT_DOUBLE_EQ(g.references()[0].q_ref, 1.0);
  EXPECT_DOUBLE_EQ(g.references()[1].q_ref, -0.5);
  EXPECT_EQ(g.clamped_total(), 2u);
}

TEST(CommandGuard, DampHoldsTheLastPositionReferenceWithScaledGains) {
  CommandGuard g(TwoJoints());
  auto c = Position(0.4, 0.0);
  c.joint[1].mode = shm::JointMode::kTorque;  // not a position: holds the measured position
  c.joint[1].tau_ff = 1.0;
  ASSERT_EQ(g.Accept(c), 0);
  const double q[2] = {0.35, 0.25};
  g.Damp(q, 0.2, 2.0);
  EXPECT_EQ(g.references()[0].mode, shm::JointMode::kPosition);
  EXPECT_DOUBLE_EQ(g.references()[0].q_ref, 0.4);
  EXPECT_DOUBLE_EQ(g.references()[1].q_ref, 0.25);
  EXPECT_DOUBLE_EQ(g.references()[1].tau_ff, 0.0);
  EXPECT_DOUBLE_EQ(g.references()[0].kp, 20.0);
  EXPECT_DOUBLE_EQ(g.references()[0].kd, 4.0);
}

}  // namespace
}  // namespace ohrp::hw
