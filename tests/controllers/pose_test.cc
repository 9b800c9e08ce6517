// Tests pose files (controllers/pose.h) and the shipped half-sitting of SampleRobot.
#include "controllers/pose.h"

#include <gtest/gtest.h>

#include "controllers/posture.h"
#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

TEST(PoseTest, ParsesJointsByNameAndZeroesTheRest) {
  Pose pose;
  ConfigStatus s = ParsePose("robot: R\njoints:\n  B: 0.5\n  C: -1e-1\n", "p.yaml", &pose);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(pose.robot, "R");
  std::vector<double> q;
  ASSERT_TRUE(ResolvePose(pose, {"A", "B", "C"}, &q).ok());
  EXPECT_EQ(q, (std::vector<double>{0.0, 0.5, -0.1}));
}

TEST(PoseTest, SaysWhichJointsThePoseNames) {
  Pose pose;
  ASSERT_TRUE(ParsePose("joints:\n  B: 0.5\n", "p.yaml", &pose).ok());
  std::vector<double> q;
  std::vector<bool> named;
  ASSERT_TRUE(ResolvePose(pose, {"A", "B", "C"}, &q, &named).ok());
  EXPECT_EQ(named, (std::vector<bool>{false, true, false}));
}

TEST(PoseTest, KeyframePoseSkipsJointsTheRobotDoesNotCommand) {
  const Pose pose = FromKeyframe("scene.xml keyframe 'home'", {{"shin", 0.1}, {"knee", -0.7}});
  std::vector<double> q;
  std::vector<bool> named;
  ASSERT_TRUE(ResolvePose(pose, {"hip", "knee"}, &q, &named).ok());
  EXPECT_EQ(q, (std::vector<double>{0.0, -0.7}));
  EXPECT_EQ(named, (std::vector<bool>{false, true}));
}

TEST(PoseTest, KeyframeOfAnotherRobotIsRefused) {
  const Pose pose = FromKeyframe("other.xml keyframe 'home'", {{"shin", 0.1}});
  std::vector<double> q;
  ConfigStatus s = ResolvePose(pose, {"hip", "knee"}, &q);
  EXPECT_EQ(s.code, ConfigError::kUnknownJoint);
  EXPECT_NE(s.message.find("names none of the robot's 2 joints (hip knee)"), std::string::npos)
      << s.message;
}

TEST(PoseTest, UnknownJointListsTheRobotsJoints) {
  Pose pose;
  ASSERT_TRUE(ParsePose("joints:\n  A: 1\n  ELBOW: 0.5\n", "p.yaml", &pose).ok());
  std::vector<double> q;
  ConfigStatus s = ResolvePose(pose, {"A", "B"}, &q);
  EXPECT_EQ(s.code, ConfigError::kUnknownJoint);
  EXPECT_NE(s.message.find("ELBOW (line 3)"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("joints are: A B"), std::string::npos) << s.message;
}

TEST(PoseTest, MalformedPosesAreRefused) {
  Pose pose;
  EXPECT_EQ(ParsePose("joints:\n  A: abc\n", "p.yaml", &pose).code, ConfigError::kSyntax);
  EXPECT_EQ(ParsePose("joints:\n  A: .nan\n", "p.yaml", &pose).code, ConfigError::kNonFinite);
  EXPECT_EQ(ParsePose("joints:\n  A: 1\n  A: 2\n", "p.yaml", &pose).code, ConfigError::kSyntax);
  EXPECT_EQ(ParsePose("joint:\n  A: 1\n", "p.yaml", &pose).code, ConfigError::kSyntax);
  EXPECT_EQ(ParsePose("robot: R\n", "p.yaml", &pose).code, ConfigError::kSyntax);
  ConfigStatus s = ParsePose("joints: [1, 2\n", "p.yaml", &pose);
  EXPECT_EQ(s.code, ConfigError::kSyntax);
  EXPECT_NE(s.message.find("p.yaml:"), std::string::npos);
  EXPECT_EQ(LoadPoseFile("/nonexistent.yaml", &pose).code, ConfigError::kFile);
}

TEST(PoseTest, HalfSittingOfSampleRobot) {
  Pose pose;
  ConfigStatus s = LoadPoseFile(DefaultPoseFile(), &pose);
  ASSERT_TRUE(s.ok()) << s.message;
  std::vector<double> q;
  s = ResolvePose(pose, testing::SampleRobotJoints(), &q);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(q.size(), 29u);
  for (int leg : {0, 13}) {
    EXPECT_DOUBLE_EQ(q[leg + 1], -0.349066);  // hip pitch
    EXPECT_DOUBLE_EQ(q[leg + 3], 0.698132);   // knee
    EXPECT_DOUBLE_EQ(q[leg + 4], -0.349066);  // ankle pitch
    EXPECT_NEAR(q[leg + 1] + q[leg + 3] + q[leg + 4], 0.0, 1e-9);  // sole parallel to the waist
  }
  EXPECT_DOUBLE_EQ(q[6], 0.174533);    // RARM_SHOULDER_P
  EXPECT_DOUBLE_EQ(q[7], -0.174533);   // RARM_SHOULDER_R: outward is negative on the right
  EXPECT_DOUBLE_EQ(q[20], 0.174533);   // LARM_SHOULDER_R: outward is positive on the left
  EXPECT_DOUBLE_EQ(q[9], -0.523599);   // RARM_ELBOW
  EXPECT_DOUBLE_EQ(q[22], -0.523599);  // LARM_ELBOW
  for (int j : {0, 2, 5, 8, 10, 11, 12, 26, 27, 28}) EXPECT_EQ(q[j], 0.0) << j;
}

}  // namespace
}  // namespace ohrp::controllers
