// Tests the joint servos: command checks joint by joint (velocity references among them), and
// the PD law against the closed form of a damped oscillator.
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "test_models.h"

namespace ohrp::sim {
namespace {

class ServoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    model::InstallMujocoHandlers(nullptr);
    std::string error;
    scene_ = model::Scene::Load(testing::WriteTemp(testing::kTwoJointArm), &error);
    ASSERT_TRUE(scene_) << error;
    ASSERT_TRUE(model::MapRobot(scene_->m(), &robot_, &error)) << error;
    servo_ = std::make_unique<model::Servo>(robot_);
    servo_->HoldCurrent(scene_->d());
  }
  shm::CommandBlock Position(double q1, double q2, double kp = 100, double kd = 10) {
    shm::CommandBlock c{};
    c.njoint = 2;
    for (int i = 0; i < 2; ++i) {
      c.joint[i].mode = shm::JointMode::kPosition;
      c.joint[i].kp = kp;
      c.joint[i].kd = kd;
    }
    c.joint[0].q_ref = q1;
    c.joint[1].q_ref = q2;
    return c;
  }
  std::unique_ptr<model::Scene> scene_;
  model::RobotMap robot_;
  std::unique_ptr<model::Servo> servo_;
};

TEST_F(ServoTest, AcceptsValidCommands) {
  EXPECT_EQ(servo_->Accept(Position(0.3, -2.0)), 0);
  EXPECT_DOUBLE_EQ(servo_->reference(0).q_ref, 0.3);
  EXPECT_DOUBLE_EQ(servo_->reference(1).q_ref, -2.0);
  EXPECT_EQ(servo_->rejected_total(), 0u);
}

TEST_F(ServoTest, RejectsNanJointByJointAndTheJointHolds) {
  servo_->Accept(Position(0.2, 0.1));
  auto c = Position(std::numeric_limits<double>::quiet_NaN(), 0.4);
  EXPECT_EQ(servo_->Accept(c), 1);
  EXPECT_DOUBLE_EQ(servo_->reference(0).q_ref, 0.2);  // held
  EXPECT_DOUBLE_EQ(servo_->reference(1).q_ref, 0.4);  // taken
  EXPECT_EQ(servo_->rejected_per_joint()[0], 1u);
  EXPECT_EQ(servo_->rejected_per_joint()[1], 0u);
}

TEST_F(ServoTest, RejectsPositionOutsideTheJointRange) {
  EXPECT_EQ(servo_->Accept(Position(1.6, 0)), 1);  // range of j1 is +-1.5
  EXPECT_EQ(servo_->Accept(Position(1.5 + 0.5 * model::kRangeTolerance, 0)), 0);
}

TEST_F(ServoTest, RejectsBadGainsModesAndTorques) {
  EXPECT_EQ(servo_->Accept(Position(0, 0, -1, 0)), 2);
  EXPECT_EQ(servo_->Accept(Position(0, 0, 2 * model::kMaxGain, 0)), 2);
  auto c = Position(0, 0);
  c.joint[0].mode = static_cast<shm::JointMode>(42);
  c.joint[1].mode = shm::JointMode::kTorque;
  c.joint[1].tau_ff = 21;  // limit of j2 is 20
  EXPECT_EQ(servo_->Accept(c), 2);
  c.joint[0].mode = shm::JointMode::kTorque;
  c.joint[0].tau_ff = std::numeric_limits<double>::infinity();
  EXPECT_EQ(servo_->Accept(c), 2);
  EXPECT_EQ(servo_->rejected_total(), 8u);
}

// dq_ref = 1e300 would drive the joint at full torque: refused like a position out of range
TEST_F(ServoTest, RejectsVelocityReferencesBeyondTheJointSpeed) {
  servo_->Accept(Position(0.2, 0.1));
  auto c = Position(0.3, 0.3);
  c.joint[0].dq_ref = 1e300;
  c.joint[1].mode = shm::JointMode::kVelocity;
  c.joint[1].dq_ref = -1.01 * model::kMaxJointSpeed;
  EXPECT_EQ(servo_->Accept(c), 2);
  EXPECT_DOUBLE_EQ(servo_->reference(0).q_ref, 0.2);  // both hold
  EXPECT_DOUBLE_EQ(servo_->reference(0).dq_ref, 0.0);
  EXPECT_EQ(servo_->reference(1).mode, shm::JointMode::kPosition);
  servo_->Apply(scene_->m(), scene_->d());
  EXPECT_LT(std::fabs(scene_->d()->ctrl[0]), 50.0);  // not at the torque limit

  c.joint[0].dq_ref = model::kMaxJointSpeed;  // the bound itself is a speed
  c.joint[1].dq_ref = -model::kMaxJointSpeed;
  EXPECT_EQ(servo_->Accept(c), 0);
}

TEST_F(ServoTest, BlockForAnotherRobotIsRejectedWhole) {
  auto c = Position(0.1, 0.1);
  c.njoint = 3;
  EXPECT_EQ(servo_->Accept(c), 2);
  EXPECT_DOUBLE_EQ(servo_->reference(0).q_ref, 0.0);
}

TEST_F(ServoTest, TorqueIsClampedToTheLimit) {
  servo_->Accept(Position(1.0, 0, 1e6, 0));
  servo_->Apply(scene_->m(), scene_->d());
  EXPECT_DOUBLE_EQ(scene_->d()->ctrl[0], 50.0);
}

// A joint whose inertia is its armature I, under tau = kp (r - q) - kd dq, is a damped
// oscillator: q(t) = r (1 - e^{-z w t} (cos(wd t) + z / sqrt(1 - z^2) sin(wd t))),
// w = sqrt(kp / I), z = kd / (2 sqrt(kp I)), wd = w sqrt(1 - z^2).
TEST_F(ServoTest, StepResponseMatchesTheDampedOscillator) {
  const double I = 2.0, kp = 80, kd = 4, r = 0.5;  // 40 N m at most: under the 50 N m limit
  const double w = std::sqrt(kp / I), z = kd / (2 * std::sqrt(kp * I));
  const double wd = w * std::sqrt(1 - z * z);
  servo_->Accept(Position(r, 0, kp, kd));
  mjModel* m = scene_->m();
  mjData* d = scene_->d();
  double worst = 0;
  for (int k = 1; k <= 2000; ++k) {
    servo_->Apply(m, d);
    mj_step(m, d);
    const double t = d->time;
    const double q = r * (1 - std::exp(-z * w * t) *
                                   (std::cos(wd * t) + z / std::sqrt(1 - z * z) * std::sin(wd * t)));
    worst = std::max(worst, std::fabs(d->qpos[0] - q));
  }
  // semi-implicit Euler at w dt = 0.01 drifts by O(w dt) of the amplitude: 1 % of the step
  EXPECT_LT(worst, 0.01 * r);
  EXPECT_GT(worst, 0.0);
}

}  // namespace
}  // namespace ohrp::sim
