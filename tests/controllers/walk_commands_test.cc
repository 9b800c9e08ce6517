// Tests the walk controller's inputs: the command lines (what each takes, what is refused and
// the message) and the YAML parameter file (strict keys, types, file:line in every error).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "common/scratch.h"
#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

std::string Temp(const std::string& name, const std::string& text) {
  const std::string path = ohrp::testing::ScratchDir() + "/walk_commands_test_" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(WalkCommand, ParsesEachCommand) {
  WalkCommand c;
  std::string error;
  ASSERT_TRUE(ParseWalkCommand("goal 1.5 -0.2 90", &c, &error)) << error;
  EXPECT_EQ(c.kind, WalkCommand::Kind::kGoal);
  EXPECT_DOUBLE_EQ(c.x, 1.5);
  EXPECT_DOUBLE_EQ(c.y, -0.2);
  EXPECT_NEAR(c.yaw, M_PI / 2, 1e-12);
  ASSERT_TRUE(ParseWalkCommand("velocity 0.2 0 10 5", &c, &error)) << error;
  EXPECT_EQ(c.kind, WalkCommand::Kind::kVelocity);
  EXPECT_NEAR(c.yaw, 10 * M_PI / 180, 1e-12);
  EXPECT_DOUBLE_EQ(c.time, 5);
  ASSERT_TRUE(ParseWalkCommand("steps scenarios/steps/mixed.yaml", &c, &error)) << error;
  EXPECT_EQ(c.kind, WalkCommand::Kind::kSteps);
  EXPECT_EQ(c.file, "scenarios/steps/mixed.yaml");
  ASSERT_TRUE(ParseWalkCommand("wait 2", &c, &error)) << error;
  EXPECT_EQ(c.kind, WalkCommand::Kind::kWait);
  EXPECT_EQ(c.text, "wait 2");
}

TEST(WalkCommand, RefusesWhatCannotBeWalked) {
  WalkCommand c;
  for (const char* bad : {"goal 1 0", "goal 1 0 0 0", "goal a b c", "goal nan 0 0",
                          "velocity 0.2 0 0", "velocity 0.2 0 0 0", "velocity 0.2 0 0 -1",
                          "wait -1", "wait", "steps", "steps a b", "run 1 0 0", ""}) {
    std::string error;
    EXPECT_FALSE(ParseWalkCommand(bad, &c, &error)) << bad;
    EXPECT_FALSE(error.empty()) << bad;
  }
  std::string error;
  ParseWalkCommand("goal 1 0", &c, &error);
  EXPECT_NE(error.find("X Y YAW_DEG"), std::string::npos) << error;  // what would work
  ParseWalkCommand("run 1 0 0", &c, &error);
  EXPECT_NE(error.find("goal, velocity, steps, wait or random"), std::string::npos) << error;
}

TEST(WalkParams, ReadsTheParameters) {
  WalkOptions o;
  const std::string path = Temp("good.yaml", "step_time: 1.0\nmax_turn_deg: 10\ncom_lower: 0.05\n");
  const ConfigStatus s = LoadWalkParams(path, &o);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_DOUBLE_EQ(o.gait.step_time, 1.0);
  EXPECT_NEAR(o.limits.max_turn, 10 * M_PI / 180, 1e-12);
  EXPECT_DOUBLE_EQ(o.com_lower, 0.05);
}

// the gait's switches (stored as flags, no value of their own: a null slot in the key table)
TEST(WalkParams, ReadsTheGaitSwitches) {
  WalkOptions o;
  const ConfigStatus s = LoadWalkParams(
      Temp("switches.yaml", "start_push: 1\nstart_rock: 1\nstop_rock: 1\nmax_turn_deg: 10\n"), &o);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_TRUE(o.gait.start_push);
  EXPECT_TRUE(o.gait.start_rock);
  EXPECT_TRUE(o.gait.stop_rock);
  EXPECT_NEAR(o.limits.max_turn, 10 * M_PI / 180, 1e-12);
  WalkOptions off;
  ASSERT_TRUE(LoadWalkParams(Temp("off.yaml", "start_rock: 0\nstop_rock: 0\n"), &off).ok());
  EXPECT_FALSE(off.gait.start_rock);
  EXPECT_FALSE(off.gait.stop_rock);
}

TEST(WalkParams, RefusesUnknownKeysAndWrongTypesWithTheLine) {
  WalkOptions o;
  ConfigStatus s = LoadWalkParams(Temp("typo.yaml", "step_time: 1.0\nstep_hieght: 0.05\n"), &o);
  EXPECT_EQ(s.code, ConfigError::kFile);
  EXPECT_NE(s.message.find("typo.yaml:2:"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("step_hieght"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("step_height"), std::string::npos) << s.message;  // the known keys
  s = LoadWalkParams(Temp("type.yaml", "step_time: slow\n"), &o);
  EXPECT_NE(s.message.find("type.yaml:1:"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("must be a number"), std::string::npos) << s.message;
  s = LoadWalkParams(Temp("list.yaml", "- 1\n- 2\n"), &o);
  EXPECT_FALSE(s.ok());
  s = LoadWalkParams(ohrp::testing::ScratchDir() + "/nosuch.yaml", &o);
  EXPECT_EQ(s.code, ConfigError::kFile);
  EXPECT_NE(s.message.find("nosuch.yaml"), std::string::npos) << s.message;
}

// a robot profile's walking: map holds the same keys (robot_model/profile.h; robots/g1.yaml)
TEST(WalkParams, AProfilesWalkingMapIsRead) {
  WalkOptions o;
  const std::string head = "model: robot.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n";
  ConfigStatus s = LoadProfileWalkParams(
      Temp("robot_profile.yaml", head + "walking: {max_forward: 0.13, max_side: 0.05}\n"), &o);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_DOUBLE_EQ(o.limits.max_forward, 0.13);
  EXPECT_DOUBLE_EQ(o.limits.max_side, 0.05);
  WalkOptions untouched;
  s = LoadProfileWalkParams(Temp("no_walking.yaml", head), &untouched);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_DOUBLE_EQ(untouched.limits.max_forward, WalkOptions{}.limits.max_forward);
  s = LoadProfileWalkParams(Temp("typo_profile.yaml", head + "walking:\n  max_froward: 0.1\n"), &o);
  EXPECT_EQ(s.code, ConfigError::kFile);
  EXPECT_NE(s.message.find("typo_profile.yaml:6:"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("max_froward"), std::string::npos) << s.message;
}

// a key set on the command line (walk_main puts it in `given`) keeps its value over the profile's
// walking: and a parameter file's; the others are read, and an unknown key is still refused
TEST(WalkParams, TheCommandLineWinsOverTheProfileAndTheParameterFile) {
  WalkOptions o;
  o.gait.step_time = 1.1;
  o.given = {"step_time"};
  const std::string head = "model: robot.xml\nfeet:\n  left: {body: l}\n  right: {body: r}\n";
  ConfigStatus s = LoadProfileWalkParams(
      Temp("keep_profile.yaml", head + "walking: {step_time: 0.9, max_side: 0.05}\n"), &o,
      o.given);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_DOUBLE_EQ(o.gait.step_time, 1.1);
  EXPECT_DOUBLE_EQ(o.limits.max_side, 0.05);
  s = LoadWalkParams(Temp("keep.yaml", "step_time: 0.7\nstep_height: 0.03\n"), &o, {"step_time"});
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_DOUBLE_EQ(o.gait.step_time, 1.1);
  EXPECT_DOUBLE_EQ(o.gait.step_height, 0.03);
  s = LoadWalkParams(Temp("keep_bad.yaml", "step_time: 99\n"), &o, {"step_time"});
  EXPECT_EQ(s.code, ConfigError::kOption) << "a kept key is still checked: " << s.message;
}

// values out of range are refused when the controller is created (before anything runs)
TEST(WalkOptions, RefusesValuesOutOfRange) {
  ConfigStatus status;
  WalkOptions o;
  o.gait.step_time = 0.05;
  EXPECT_FALSE(WalkController::Create(o, &status));
  EXPECT_EQ(status.code, ConfigError::kOption);
  EXPECT_NE(status.message.find("step_time"), std::string::npos) << status.message;
  o = WalkOptions{};
  o.com_lower = -0.1;
  EXPECT_FALSE(WalkController::Create(o, &status));
  EXPECT_NE(status.message.find("com_lower"), std::string::npos) << status.message;
  o = WalkOptions{};
  o.preview.preview_time = 0.1;
  EXPECT_FALSE(WalkController::Create(o, &status));
  EXPECT_NE(status.message.find("preview_time"), std::string::npos) << status.message;
}

}  // namespace
}  // namespace ohrp::controllers
