// Tests scene loading and the robot map: what sim_host publishes and what it refuses.
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

#include <gtest/gtest.h>

#include "test_models.h"

namespace ohrp::sim {
namespace {

class ModelTest : public ::testing::Test {
 protected:
  void SetUp() override { model::InstallMujocoHandlers(nullptr); }
};

TEST_F(ModelTest, MapsMotorsForceSensorsAndGains) {
  std::string error;
  auto scene = model::Scene::Load(testing::WriteTemp(testing::kTwoJointArm), &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  EXPECT_EQ(robot.name, "arm");
  ASSERT_EQ(robot.joints.size(), 2u);
  EXPECT_EQ(robot.joints[0].name, "j1");
  EXPECT_DOUBLE_EQ(robot.joints[0].q_min, -1.5);
  EXPECT_DOUBLE_EQ(robot.joints[0].tau_max, 50);
  EXPECT_DOUBLE_EQ(robot.joints[1].q_max, model::kNoLimit);
  // default gains: a critically damped 6 Hz servo on the joint's own inertia (the armature)
  const double w = 2 * M_PI * 6.0;
  EXPECT_NEAR(robot.joints[0].default_kp, 2.0 * w * w, 1e-3 * 2.0 * w * w);
  EXPECT_NEAR(robot.joints[0].default_kd, 2 * 2.0 * w, 1e-3 * 4.0 * w);
  ASSERT_EQ(robot.forces.size(), 1u);
  EXPECT_EQ(robot.forces[0].name, "tip");
  EXPECT_EQ(robot.base_body, -1);
}

TEST_F(ModelTest, MalformedSceneNamesTheFileAndMujocosError) {
  const std::string path = testing::WriteTemp("<mujoco><worldbody><body><geom type='sphere'/></worldbody></mujoco>");
  std::string error;
  EXPECT_FALSE(model::Scene::Load(path, &error));
  EXPECT_NE(error.find(path), std::string::npos) << error;
  EXPECT_NE(error.find("XML"), std::string::npos) << error;
}

TEST_F(ModelTest, MissingSceneIsAnError) {
  std::string error;
  EXPECT_FALSE(model::Scene::Load("/nonexistent/scene.xml", &error));
  EXPECT_NE(error.find("/nonexistent/scene.xml"), std::string::npos);
}

TEST_F(ModelTest, RefusesAModelWithoutMotors) {
  std::string error;
  auto scene = model::Scene::Load(testing::WriteTemp(testing::kNoMotors), &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  EXPECT_FALSE(model::MapRobot(scene->m(), &robot, &error));
  EXPECT_NE(error.find("no <motor>"), std::string::npos) << error;
}

TEST_F(ModelTest, MapsAGearedMotor) {
  std::string error;
  auto scene = model::Scene::Load(testing::WriteTemp(testing::kGearedMotor), &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  ASSERT_EQ(robot.joints.size(), 1u);
  EXPECT_DOUBLE_EQ(robot.joints[0].law.gear, 2.0);
  EXPECT_EQ(robot.joints[0].law.kind, model::ActuatorKind::kMotor);
}

TEST_F(ModelTest, RefusesAnActuatorWithActivationDynamics) {
  std::string error;
  auto scene = model::Scene::Load(testing::WriteTemp(testing::kFilteredActuator), &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  EXPECT_FALSE(model::MapRobot(scene->m(), &robot, &error));
  EXPECT_NE(error.find("activation dynamics"), std::string::npos) << error;
}

TEST_F(ModelTest, UnknownKeyframeIsAnError) {
  std::string error;
  auto scene = model::Scene::Load(testing::WriteTemp(testing::kTwoJointArm), &error);
  ASSERT_TRUE(scene);
  EXPECT_FALSE(scene->Reset("nope", &error));
  EXPECT_NE(error.find("no keyframe 'nope'"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::sim
