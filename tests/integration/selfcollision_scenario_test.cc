// The self-collision scenario (issue 15): playback swings HRP-1S's right arm into its right leg
// (scenarios/selfcollision_arm_{on,off}.yaml, run by ohrp_run in its own processes: sim_host and
// playback). The data log's joint angles are measured with the checker and the shipped file:
// with the online check on the arm stops short of the leg and playback reports the held
// cycles naming the pair; with it off the hand goes into the thigh.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "temp_file.h"

namespace ohrp::collision {
namespace {

std::string Src(const std::string& p) { return std::string(OHRP_SOURCE_DIR) + "/" + p; }

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// runs a scenario into a fresh folder; returns the folder
std::string RunScenario(const std::string& scenario) {
  const std::string out = runner::TempDir();
  const std::string cmd = "cd " + std::string(OHRP_SOURCE_DIR) + " && " + OHRP_BIN_DIR +
                          "/ohrp_run " + scenario + " --out " + out + " --quiet --no-plot";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return out;
}

// the smallest distance between a right-arm link and a right-leg link over the logged run [m]
double ArmLegDistance(const std::string& log_path) {
  SelfCollisionFile file;
  std::string error;
  EXPECT_TRUE(ReadSelfCollisionFile(Src("mjcf/hrp1s/selfcollision.yaml"), &file, &error)) << error;
  auto checker = SelfCollision::Create(file.robot, &error);
  const RobotGeometry& g = file.robot;
  std::ifstream in(log_path);
  std::string line, cell;
  std::getline(in, line);
  // the columns of q_<joint>, in the file's joint order
  std::vector<std::string> head;
  for (std::stringstream s(line); std::getline(s, cell, ',');) head.push_back(cell);
  std::vector<int> col;
  for (const auto& name : g.joint_names)
    col.push_back(static_cast<int>(std::find(head.begin(), head.end(), "q_" + name) - head.begin()));
  std::vector<LinkPair> pairs;
  for (size_t a = 0; a < g.links.size(); ++a)
    for (size_t b = 0; b < g.links.size(); ++b)
      if (g.links[a].name.rfind("RARM_", 0) == 0 && g.links[b].name.rfind("RLEG_", 0) == 0)
        pairs.push_back({static_cast<int>(std::min(a, b)), static_cast<int>(std::max(a, b))});
  double closest = INFINITY;
  std::vector<double> row, q(g.joint_names.size());
  while (std::getline(in, line)) {
    row.clear();
    for (std::stringstream s(line); std::getline(s, cell, ',');) row.push_back(std::atof(cell.c_str()));
    for (size_t j = 0; j < q.size(); ++j) q[j] = row.at(col[j]);
    checker->SetPose(q);
    closest = std::min(closest, checker->Check(pairs, 0.05, {}).min_distance);
  }
  return closest;
}

TEST(SelfCollisionScenario, WithoutTheCheckTheArmGoesIntoTheLeg) {
  const std::string out = RunScenario("scenarios/selfcollision_arm_off.yaml");
  EXPECT_LT(ArmLegDistance(out + "/log.csv"), -0.005);
}

TEST(SelfCollisionScenario, TheCheckStopsTheArmBeforeTheLeg) {
  const std::string out = RunScenario("scenarios/selfcollision_arm_on.yaml");
  // stopped before contact: the servo lags the held reference by little
  EXPECT_GT(ArmLegDistance(out + "/log.csv"), 0.0);
  const std::string said = ReadAll(out + "/playback.stderr");
  EXPECT_NE(said.find("self-collision: held the last safe references"), std::string::npos) << said;
  EXPECT_NE(said.find("RARM_"), std::string::npos) << said;
}

}  // namespace
}  // namespace ohrp::collision
