// Tests the run's command lines and their placeholders (tools/runner/src/commands.cc): `{out}`
// in a controller's args and in sim_args becomes the output folder, any other `{...}` is named
// as unknown; and the files summary.json lists (runner.cc's OutputFiles).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "runner/commands.h"
#include "robot_model/joint_params.h"
#include "runner/runner.h"
#include "temp_file.h"

namespace ohrp::runner {
namespace {

bool Contains(const std::vector<std::string>& argv, const std::string& a) {
  return std::find(argv.begin(), argv.end(), a) != argv.end();
}

TEST(Placeholders, OutBecomesTheOutputFolder) {
  EXPECT_EQ(ExpandPlaceholders("{out}/walk.csv", "/runs/a"), "/runs/a/walk.csv");
  EXPECT_EQ(ExpandPlaceholders("{out}:{out}", "/r"), "/r:/r");
  EXPECT_EQ(ExpandPlaceholders("--x", "/r"), "--x");
  // a folder whose own name holds the placeholder is not expanded again
  EXPECT_EQ(ExpandPlaceholders("{out}/a", "/r/{out}"), "/r/{out}/a");
}

TEST(Placeholders, OnlyOutIsKnown) {
  EXPECT_EQ(UnknownPlaceholder("{out}/walk.csv"), "");
  EXPECT_EQ(UnknownPlaceholder("--ramp"), "");
  EXPECT_EQ(UnknownPlaceholder("a{b"), "");  // no closing brace: plain text
  const std::string why = UnknownPlaceholder("{out}/{output}.csv");
  EXPECT_NE(why.find("unknown placeholder '{output}' in '{out}/{output}.csv'"), std::string::npos) << why;
  EXPECT_NE(why.find("the only one is {out}"), std::string::npos) << why;
  EXPECT_NE(UnknownPlaceholder("{}"), "");
  EXPECT_NE(UnknownPlaceholder("{OUT}"), "");
}

TEST(Commands, ControllerArgumentsGetTheOutputFolder) {
  ControllerSpec walk;
  walk.program = "walk";
  walk.args = {"--log", "{out}/walk.csv"};
  const auto argv = ControllerCommand(walk, "/bin/walk", "seg", "/runs/w");
  EXPECT_EQ(argv, (std::vector<std::string>{"/bin/walk", "--segment", "seg", "--attach-timeout",
                                            "10", "--log", "/runs/w/walk.csv"}));
}

TEST(Commands, SimArgumentsGetTheOutputFolder) {
  Scenario s;
  s.sim_args = {"--progress", "0", "--extra", "{out}/x.json"};
  const auto argv = SimHostCommand(s, "/bin/sim_host", "scene.xml", "seg", "/runs/w");
  EXPECT_TRUE(Contains(argv, "/runs/w/x.json"));
  EXPECT_TRUE(Contains(argv, "/runs/w/log.csv"));
  EXPECT_FALSE(Contains(argv, "{out}/x.json"));
  EXPECT_EQ(argv.back(), "/runs/w/x.json");
}

// a scenario without control_period leaves the period to sim_host (the multiple of the scene's
// step nearest 5 ms: 4 ms for H1's 2 ms step), one with it passes it on
TEST(Commands, TheControlPeriodIsPassedOnlyWhenTheScenarioSetsIt) {
  Scenario s;
  EXPECT_EQ(s.control_period, 0.0);
  auto argv = SimHostCommand(s, "/bin/sim_host", "scene.xml", "seg", "/runs/w");
  EXPECT_FALSE(Contains(argv, "--control-period"));
  s.control_period = 0.004;
  argv = SimHostCommand(s, "/bin/sim_host", "scene.xml", "seg", "/runs/w");
  const auto at = std::find(argv.begin(), argv.end(), "--control-period");
  ASSERT_NE(at, argv.end());
  EXPECT_EQ(std::stod(*(at + 1)), 0.004);
}

// issue 35: a scenario's joint_params become the run folder's joint_params.yaml, which sim_host
// applies with --joint-file; the file reads back as written
TEST(Commands, JointParamsGoToSimHostAsAFileInTheRunFolder) {
  Scenario s;
  auto argv = SimHostCommand(s, "/bin/sim_host", "scene.xml", "seg", "/runs/w");
  EXPECT_FALSE(Contains(argv, "--joint-file"));
  s.joint_params["LARM_ELBOW"] = {{"armature", 15.0}, {"frictionloss", 1.5}};
  s.joint_params["RLEG_KNEE"] = {{"damping", 0.25}};
  argv = SimHostCommand(s, "/bin/sim_host", "scene.xml", "seg", "/runs/w");
  const auto at = std::find(argv.begin(), argv.end(), "--joint-file");
  ASSERT_NE(at, argv.end());
  EXPECT_EQ(*(at + 1), "/runs/w/joint_params.yaml");
  const std::string file = TempDir() + "/joint_params.yaml";
  std::string error;
  ASSERT_TRUE(WriteJointParams(s, file, &error)) << error;
  std::vector<model::JointParams> read;
  ASSERT_TRUE(model::ReadJointParamsFile(file, &read, &error)) << error;
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0].joint, "LARM_ELBOW");
  EXPECT_EQ(read[0].armature, 15.0);
  EXPECT_TRUE(std::isnan(read[0].damping));  // left out: the model's
  EXPECT_EQ(read[0].frictionloss, 1.5);
  EXPECT_EQ(read[1].joint, "RLEG_KNEE");
  EXPECT_EQ(read[1].damping, 0.25);
  EXPECT_FALSE(WriteJointParams(s, "/nonexistent-folder/joint_params.yaml", &error));
  EXPECT_NE(error.find("cannot write /nonexistent-folder/joint_params.yaml"), std::string::npos);
}

TEST(OutputFiles, ListsTheWalkLogWhenAControllerWroteIt) {
  const std::string dir = TempDir();
  auto files = OutputFiles(dir);
  EXPECT_EQ(files.count("walk"), 0u);
  EXPECT_EQ(files.at("log"), "log.csv");
  std::ofstream(dir + "/walk.csv") << "t\n";
  files = OutputFiles(dir);
  EXPECT_EQ(files.at("walk"), "walk.csv");
}

}  // namespace
}  // namespace ohrp::runner
