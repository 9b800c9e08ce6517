// Tests the run's command lines and their placeholders (tools/runner/src/commands.cc): `{out}`
// in a controller's args and in sim_args becomes the output folder, any other `{...}` is named
// as unknown; and the files summary.json lists (runner.cc's OutputFiles).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "runner/commands.h"
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
