// Tests the posture program across processes: a fake robot (Producer) in the test, the built
// `posture` binary attached to it.
#include "controllers/posture.h"

#include <gtest/gtest.h>

#include "controllers/pose.h"
#include "controllers/ramp.h"
#include "controllers/runner.h"
#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

using testing::FakeRobot;
using testing::FakeRobotSpec;

class PostureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = testing::UniqueSegment("posture");
    testing::RemoveSegment(segment_);
    log_ = testing::TempPath("posture_log");
  }
  void TearDown() override {
    testing::RemoveSegment(segment_);
    std::remove(log_.c_str());
  }
  std::string segment_, log_;
};

TEST_F(PostureTest, ConvergesToHalfSittingAlongARampInProducerTime) {
  FakeRobotSpec spec;
  spec.segment = segment_;
  spec.joints = testing::SampleRobotJoints();
  spec.q_init.assign(29, 0.05);  // some pose other than the target
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  const double ramp = 0.5;  // [s] = 100 cycles of 5 ms
  pid_t pid = testing::Spawn({testing::Program("posture"), "--segment", segment_, "--ramp",
                              "0.5", "--kp-scale", "2", "--attach-timeout", "5"},
                             log_);
  ASSERT_TRUE(robot->RunUntilCommands(160)) << testing::ReadFile(log_);

  Pose pose;
  ASSERT_TRUE(LoadPoseFile(DefaultPoseFile(), &pose).ok());
  std::vector<double> target;
  std::vector<bool> named;
  ASSERT_TRUE(ResolvePose(pose, spec.joints, &target, &named).ok());
  for (int j = 0; j < 29; ++j) {
    if (!named[j]) target[j] = 0.05;  // joints the pose leaves out hold where they were
  }
  const auto& rec = robot->records();
  // knee reference error against the ramp started at t0 from the initial pose
  auto knee_error = [](double t0, const testing::CommandRecord& r, const void* ctx) {
    const double knee = *static_cast<const double*>(ctx);
    return r.q_ref[3] - (0.05 + (knee - 0.05) * MinimumJerk((r.time - t0) / 0.5));
  };
  const double t0 = testing::FindStartTime(rec, robot->period(), knee_error, &target[3]);
  // starts at the current pose
  for (int j = 0; j < 29; ++j) EXPECT_NEAR(rec.front().q_ref[j], 0.05, 1e-3) << j;
  double prev_knee = rec.front().q_ref[3];
  for (const auto& r : rec) {
    // the ramp follows the producer's time, whatever the cycle count
    const double s = MinimumJerk((r.time - t0) / ramp);
    EXPECT_NEAR(r.q_ref[3], 0.05 + (target[3] - 0.05) * s, 1e-9) << "at t = " << r.time;
    EXPECT_GE(r.q_ref[3], prev_knee - 1e-12);  // the knee only bends further
    prev_knee = r.q_ref[3];
    EXPECT_EQ(r.mode[3], shm::JointMode::kPosition);
    EXPECT_DOUBLE_EQ(r.kp[3], 200.0);  // default 100 x --kp-scale 2
    EXPECT_DOUBLE_EQ(r.kd[3], 2.0);
  }
  // then holds the pose
  for (int j = 0; j < 29; ++j) {
    EXPECT_NEAR(rec.back().q_ref[j], target[j], 1e-12) << spec.joints[j];
    EXPECT_EQ(rec.back().dq_ref[j], 0.0);
  }

  robot->Stop();  // the producer ends its run normally
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitOk) << testing::ReadFile(log_);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("robot SampleRobot, 29 joints, control period 5.000 ms"), std::string::npos)
      << log;
  EXPECT_NE(log.find("ended its run"), std::string::npos) << log;
}

// runs posture (extra arguments `args`) against a three-joint robot starting at `q_init` until
// it holds; returns the last command block
testing::CommandRecord HoldOnThreeJoints(const std::string& segment, const std::string& log,
                                         const std::vector<std::string>& args) {
  FakeRobotSpec spec;
  spec.segment = segment;
  spec.robot_name = "leg";
  spec.joints = {"hip", "knee", "ankle"};
  spec.q_init = {0.3, -0.2, 0.1};
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  EXPECT_TRUE(robot) << error;
  if (!robot) return {};
  std::vector<std::string> argv = {testing::Program("posture"), "--segment", segment, "--ramp",
                                   "0.1", "--attach-timeout", "5"};
  argv.insert(argv.end(), args.begin(), args.end());
  const pid_t pid = testing::Spawn(argv, log);
  EXPECT_TRUE(robot->RunUntilCommands(60)) << testing::ReadFile(log);
  robot->Stop();
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitOk) << testing::ReadFile(log);
  return robot->records().empty() ? testing::CommandRecord{} : robot->records().back();
}

TEST_F(PostureTest, JointsAPoseFileLeavesOutHoldWhereTheyAre) {
  const std::string pose = testing::TempPath("pose");
  testing::WriteText(pose, "joints:\n  knee: 0.8\n");
  const testing::CommandRecord last = HoldOnThreeJoints(segment_, log_, {"--pose", pose});
  ASSERT_EQ(last.q_ref.size(), 3u);
  EXPECT_DOUBLE_EQ(last.q_ref[0], 0.3);  // held, not 0
  EXPECT_DOUBLE_EQ(last.q_ref[1], 0.8);
  EXPECT_DOUBLE_EQ(last.q_ref[2], 0.1);
  std::remove(pose.c_str());
}

// a scene of the same three joints, a passive one, and a keyframe
constexpr char kLegScene[] = R"(<mujoco model="leg"><compiler angle="radian"/><worldbody>
  <body><joint name="hip" axis="0 1 0"/><geom size="0.1" mass="1"/>
  <body><joint name="spring" axis="0 1 0"/><geom size="0.1" mass="1"/>
  <body><joint name="knee" axis="0 1 0"/><geom size="0.1" mass="1"/>
  <body><joint name="ankle" axis="0 1 0"/><geom size="0.1" mass="1"/></body></body></body></body>
  </worldbody><actuator><motor joint="hip"/><motor joint="knee"/><motor joint="ankle"/></actuator>
  <keyframe><key name="crouch" qpos="-0.4 0.05 0.9 -0.5"/></keyframe></mujoco>)";

TEST_F(PostureTest, TakesItsTargetFromAKeyframeOfTheScene) {
  const std::string scene = testing::TempPath("scene");
  testing::WriteText(scene, kLegScene);
  const testing::CommandRecord last =
      HoldOnThreeJoints(segment_, log_, {"--scene", scene, "--keyframe", "crouch"});
  ASSERT_EQ(last.q_ref.size(), 3u);
  EXPECT_DOUBLE_EQ(last.q_ref[0], -0.4);
  EXPECT_DOUBLE_EQ(last.q_ref[1], 0.9);  // the passive spring's 0.05 is skipped
  EXPECT_DOUBLE_EQ(last.q_ref[2], -0.5);
  std::remove(scene.c_str());
}

TEST_F(PostureTest, UnknownKeyframeIsAUsageErrorNamingTheScenesKeyframes) {
  const std::string scene = testing::TempPath("scene");
  testing::WriteText(scene, kLegScene);
  pid_t pid = testing::Spawn({testing::Program("posture"), "--segment", segment_, "--scene",
                              scene, "--keyframe", "home"}, log_);
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitUsage);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("no keyframe 'home' (its keyframes: crouch)"), std::string::npos) << log;
  pid = testing::Spawn({testing::Program("posture"), "--segment", segment_, "--keyframe", "crouch"},
                       log_);
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitUsage) << testing::ReadFile(log_);  // no --scene
  std::remove(scene.c_str());
}

TEST_F(PostureTest, RefusesARobotWhoseJointsAreNotInThePose) {
  FakeRobotSpec spec;
  spec.segment = segment_;
  spec.robot_name = "Arm3";
  spec.joints = {"J0", "J1", "J2"};
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = testing::Spawn({testing::Program("posture"), "--segment", segment_}, log_);
  EXPECT_EQ(robot->RunUntilExit(pid), kExitConfig);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("has no joints RLEG_HIP_P"), std::string::npos) << log;
  EXPECT_NE(log.find("joints are: J0 J1 J2"), std::string::npos) << log;
  EXPECT_TRUE(robot->records().empty());
}

TEST_F(PostureTest, ReportsAMalformedPoseFileBeforeAttaching) {
  const std::string pose = testing::TempPath("pose");
  testing::WriteText(pose, "joints:\n  RLEG_KNEE: forty\n");
  pid_t pid = testing::Spawn(
      {testing::Program("posture"), "--segment", segment_, "--pose", pose}, log_);
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitConfig);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find(pose + ":2:"), std::string::npos) << log;
  std::remove(pose.c_str());
}

TEST_F(PostureTest, RejectsBadOptions) {
  pid_t pid = testing::Spawn({testing::Program("posture"), "--segment", segment_, "--ramp",
                              "-1"}, log_);
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitUsage) << testing::ReadFile(log_);
  pid = testing::Spawn({testing::Program("posture")}, log_);  // --segment missing
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitUsage) << testing::ReadFile(log_);
}

}  // namespace
}  // namespace ohrp::controllers
