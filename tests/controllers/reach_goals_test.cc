// reach's goals file (controllers/reach_goals.h, issue 34 item 2): the shape it reads and the
// FILE:LINE: KEY: what of each error.
#include "controllers/reach_goals.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace {

using ohrp::controllers::GoalsFile;
using ohrp::controllers::ReadGoalsFile;

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// the error for `text`, empty when it is read
std::string ErrorOf(const std::string& text) {
  const std::string path = Write("goals.yaml", text);
  GoalsFile f;
  std::string error;
  if (ReadGoalsFile(path, &f, &error)) return "";
  EXPECT_EQ(error.rfind(path + ":", 0), 0u) << error;  // starts with the file's name
  return error.substr(path.size());
}

TEST(ReachGoalsFile, ReadsJointsAndPoseGoalsWithHolds) {
  const std::string path = Write("ok.yaml",
      "group: [A, B]\n"
      "goals:\n"
      "  - joints: {A: 0.5, B: -1}\n"
      "    hold: 2\n"
      "  - pose: {site: hand, position: [0.1, 0.2, 0.3], rpy: [0, -1.5, 0.25]}\n"
      "  - pose: {site: hand, position: [1, 2, 3]}\n"
      "  - pose: [{site: left, position: [0.2, 0.1, 0.1]}, {site: right, position: [0.2, -0.1, 0.1]}]\n");
  GoalsFile f;
  std::string error;
  ASSERT_TRUE(ReadGoalsFile(path, &f, &error)) << error;
  ASSERT_EQ(f.group, (std::vector<std::string>{"A", "B"}));
  ASSERT_EQ(f.goals.size(), 4u);
  EXPECT_TRUE(f.goals[0].hands.empty());
  ASSERT_EQ(f.goals[0].joints.size(), 2u);
  EXPECT_EQ(f.goals[0].joints[0].first, "A");
  EXPECT_EQ(f.goals[0].joints[0].second, 0.5);
  EXPECT_EQ(f.goals[0].joints[1].second, -1.0);
  EXPECT_EQ(f.goals[0].hold, 2.0);
  EXPECT_EQ(f.goals[0].line, 3);
  ASSERT_EQ(f.goals[1].hands.size(), 1u);
  EXPECT_EQ(f.goals[1].hands[0].site, "hand");
  EXPECT_TRUE(f.goals[1].hands[0].p_B.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(f.goals[1].hands[0].orientation);
  EXPECT_TRUE(f.goals[1].hands[0].rpy.isApprox(Eigen::Vector3d(0, -1.5, 0.25)));
  EXPECT_LT(f.goals[1].hold, 0);  // the command line's --hold
  ASSERT_EQ(f.goals[2].hands.size(), 1u);
  EXPECT_FALSE(f.goals[2].hands[0].orientation);
  EXPECT_EQ(f.goals[2].line, 6);
  // both hands: a list of poses, one per limb
  ASSERT_EQ(f.goals[3].hands.size(), 2u);
  EXPECT_EQ(f.goals[3].hands[0].site, "left");
  EXPECT_EQ(f.goals[3].hands[1].site, "right");
  EXPECT_TRUE(f.goals[3].hands[1].p_B.isApprox(Eigen::Vector3d(0.2, -0.1, 0.1)));
}

TEST(ReachGoalsFile, TheGroupMayComeFromTheFirstJointsGoal) {
  EXPECT_EQ(ErrorOf("goals:\n  - joints: {A: 1}\n"), "");
}

TEST(ReachGoalsFile, ErrorsNameTheLineAndTheKey) {
  EXPECT_EQ(ErrorOf("group: [A]\n"), ":1: goals: missing (a list of goals)");
  EXPECT_EQ(ErrorOf("goals: []\n"), ":1: goals: give a list of at least one goal");
  EXPECT_EQ(ErrorOf("goals:\n  - joints: {A: 1}\n  - joints: {A: x}\n"),
            ":3: joints: A: 'x' is not a number");
  EXPECT_EQ(ErrorOf("goals:\n  - joints: {A: 1}\n    hold: -1\n").substr(0, 15), ":3: hold: -1 is");
  EXPECT_EQ(ErrorOf("goals:\n  - joints: {A: 1}\n    speed: 2\n").substr(0, 31),
            ":3: speed: unknown key in a goa");
  EXPECT_EQ(ErrorOf("goals:\n  - {joints: {A: 1}, pose: {site: h, position: [0, 0, 0]}}\n").substr(0, 14),
            ":2: goals: giv");
  EXPECT_EQ(ErrorOf("group: [A]\ngoals:\n  - pose: {site: h}\n"),
            ":3: pose: position: missing ([x, y, z] in the base frame, m)");
  EXPECT_EQ(ErrorOf("group: [A]\ngoals:\n  - pose: {site: h, position: [0, 0]}\n"),
            ":3: pose: position: give three numbers [a, b, c]");
  EXPECT_EQ(ErrorOf("group: [A]\ngoals:\n  - pose: [{site: h, position: [0, 0, 0]}, {site: k}]\n"),
            ":3: pose: position: missing ([x, y, z] in the base frame, m)");
  EXPECT_EQ(ErrorOf("goals:\n  - pose: {site: h, position: [0, 0, 0]}\n"),
            ":2: group: missing: a pose goal needs the group (the joints the plan moves)");
  EXPECT_EQ(ErrorOf("colour: red\ngoals:\n  - joints: {A: 1}\n").substr(0, 33),
            ":1: colour: unknown key in the fi");
  EXPECT_EQ(ErrorOf("goals:\n  - joints: {A: 1\n").substr(0, 3), ":3:");  // YAML's own error
}

TEST(ReachGoalsFile, AMissingFileIsRefused) {
  GoalsFile f;
  std::string error;
  EXPECT_FALSE(ReadGoalsFile("/nonexistent/goals.yaml", &f, &error));
  EXPECT_EQ(error, "/nonexistent/goals.yaml: cannot read the goals file");
}

}  // namespace
