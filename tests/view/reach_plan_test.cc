// The viewer's reach plan (view/reach_plan.h, tools/view/src/replay_reach.cc) on closed forms:
// the plan log read back with its errors' lines, a motion found on the log's time line where it
// began, the outermost bodies of a group, and a replayed run's hand path: a two-link arm whose
// shoulder turns a quarter turn moves its elbow (the tip body's origin) along a circle.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "view/reach_plan.h"
#include "view/source.h"

namespace fs = std::filesystem;
using namespace ohrp::view;

namespace {

std::string Write(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::string ErrorOf(const std::string& text) {
  const std::string path = Write("bad_plan.csv", text);
  ReachPlanLog log;
  std::string error;
  if (ReadReachPlanLog(path, &log, &error)) return "";
  return error.substr(path.size());
}

}  // namespace

TEST(ReachPlanLog, GoalsAndKindsAreReadBack) {
  const std::string path = Write("plan.csv",
      "# reach plan: goal 1: solved; goal 2: not solved: no path\n"
      "goal,kind,t,A,B\n"
      "1,waypoint,0.0000,0.1,0.2\n1,waypoint,1.0000,0.3,0.4\n"
      "1,planned,0.0000,0.1,0.2\n1,planned,0.0100,0.11,0.21\n"
      "1,measured,0.0000,0.1,0.2\n");
  ReachPlanLog log;
  std::string error;
  ASSERT_TRUE(ReadReachPlanLog(path, &log, &error)) << error;
  EXPECT_EQ(log.joints, (std::vector<std::string>{"A", "B"}));
  ASSERT_EQ(log.goals.size(), 1u);  // goal 2 has no rows
  EXPECT_TRUE(log.goals[0].solved);
  EXPECT_EQ(log.goals[0].waypoints.size(), 2u);
  EXPECT_EQ(log.goals[0].planned.size(), 2u);
  EXPECT_EQ(log.goals[0].measured.size(), 1u);
  EXPECT_DOUBLE_EQ(log.goals[0].planned[1].q[1], 0.21);
}

TEST(ReachPlanLog, MistakesNameTheLine) {
  EXPECT_EQ(ErrorOf("kind,t,A\n"), ":1: the header is not goal,kind,t,JOINT... (a reach --plan-log file)");
  EXPECT_EQ(ErrorOf("goal,kind,t,A\n1,planned,0\n"), ":2: 3 values, the header has 4");
  EXPECT_EQ(ErrorOf("goal,kind,t,A\n1,planned,0,x\n"), ":2: A 'x' is not a number");
  EXPECT_EQ(ErrorOf("goal,kind,t,A\n1,flown,0,1\n"), ":2: kind 'flown' is not waypoint, planned or measured");
  EXPECT_EQ(ErrorOf("goal,kind,t,A\n0,planned,0,1\n"), ":2: goal '0' is not 1, 2, ...");
  EXPECT_EQ(ErrorOf("goal,kind,t,A\n"), ":1: no rows");
}

// the log: at rest until 1.23 s, then q = 0.5 (t - 1.23); the measured motion over 1 s begins
// where the log's does, to within one log period (5 ms)
TEST(ReachPlanAlign, TheMotionStartsWhereTheLogsDoes) {
  std::vector<double> times;
  for (int i = 0; i <= 600; ++i) times.push_back(0.005 * i);
  const double T0 = 1.23;
  auto q_at = [&](double t) { return std::vector<double>{t < T0 ? 0.0 : 0.5 * (t - T0)}; };
  std::vector<ReachPlanRow> m;
  for (int i = 0; i <= 200; ++i) m.push_back({0.005 * i, {0.5 * 0.005 * i}});
  EXPECT_NEAR(AlignMotion(m, times, q_at), T0, 0.005);
  EXPECT_TRUE(std::isnan(AlignMotion({}, times, q_at)));
}

// bodies 1 -> 2 -> 3 and 1 -> 4: of the joints' bodies {2, 3, 4} the outermost are 3 and 4
TEST(ReachPlanTips, TheOutermostBodiesOfTheGroup) {
  const int parent[5] = {0, 0, 1, 2, 1};
  EXPECT_EQ(TipBodies({2, 3, 4}, parent), (std::vector<int>{3, 4}));
  EXPECT_EQ(TipBodies({2}, parent), (std::vector<int>{2}));
}

// a replayed run: a free base at z = 1 with a shoulder (hinge about y) and, 0.5 m below it, an
// elbow (hinge about y); the plan turns the shoulder from 0 to pi/2 in 1 s from t = 2 s. The
// elbow's origin goes along the circle of radius 0.5 about the shoulder, from straight below it
// to 0.5 m behind it (a turn about +y takes -z to -x)
TEST(ReachPlanReplay, TheHandPathIsTheClosedFormsCircle) {
  const fs::path dir = fs::path(::testing::TempDir()) / "reach_plan_run";
  fs::create_directories(dir);
  const std::string scene = (dir / "arm.xml").string();
  std::ofstream(scene) << R"(<mujoco model="arm"><worldbody><geom type="plane" size="5 5 0.1"/>
    <body name="base" pos="0 0 1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/>
      <body name="upper" pos="0 0 0"><joint name="shoulder" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02"/>
        <body name="lower" pos="0 0 -0.5"><joint name="elbow" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.02"/></body></body></body>
    </worldbody><actuator><motor joint="shoulder"/><motor joint="elbow"/></actuator></mujoco>)";
  std::ofstream(dir / "sim_summary.json") << "{\"scene\": \"" << scene << "\"}";
  auto shoulder = [](double t) { return t < 2 ? 0.0 : t > 3 ? M_PI / 2 : M_PI / 2 * (t - 2); };
  {
    std::ofstream log(dir / "log.csv");
    log.precision(17);
    log << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz,q_shoulder,q_elbow\n";
    for (int i = 0; i <= 800; ++i) log << 0.005 * i << ",0,0,1,1,0,0,0," << shoulder(0.005 * i) << ",0\n";
    std::ofstream plan(dir / "plan.csv");
    plan.precision(17);
    plan << "# reach plan: goal 1: solved\ngoal,kind,t,shoulder,elbow\n";
    plan << "1,waypoint,0," << 0.0 << ",0\n1,waypoint,1," << M_PI / 2 << ",0\n";
    for (int i = 0; i <= 100; ++i) plan << "1,planned," << 0.01 * i << "," << shoulder(2 + 0.01 * i) << ",0\n";
    for (int i = 0; i <= 300; ++i) plan << "1,measured," << 0.005 * i << "," << shoulder(2 + 0.005 * i) << ",0\n";
  }
  std::string error;
  auto src = ReplaySource::Open(dir.string(), "", &error);
  ASSERT_TRUE(src) << error;
  const nlohmann::json reach = src->Hello()["reach"];
  ASSERT_TRUE(reach.contains("goals")) << reach.dump();
  EXPECT_EQ(reach["hands"], nlohmann::json({"lower"}));
  const nlohmann::json& g = reach["goals"][0];
  EXPECT_NEAR(g["t_start"].get<double>(), 2.0, 0.005);
  EXPECT_NEAR(g["t_end"].get<double>(), 3.5, 0.005);
  const nlohmann::json& path = g["paths"][0];
  ASSERT_GE(path.size(), 50u);
  for (const auto& p : path) {  // on the circle about the shoulder (0, 0, 1), in the x-z plane
    EXPECT_NEAR(std::hypot(p[0].get<double>(), p[2].get<double>() - 1.0), 0.5, 1e-9);
    EXPECT_NEAR(p[1].get<double>(), 0.0, 1e-12);
  }
  EXPECT_NEAR(path.front()[2].get<double>(), 0.5, 1e-9);  // straight below
  EXPECT_NEAR(path.back()[0].get<double>(), -0.5, 1e-9);  // behind, at the shoulder's height
  EXPECT_NEAR(path.back()[2].get<double>(), 1.0, 1e-9);
  EXPECT_EQ(g["waypoints"][0].size(), 2u);
}

TEST(ReachPlanReplay, NoPlanLogIsSaid) {
  const fs::path dir = fs::path(::testing::TempDir()) / "reach_plan_run";
  fs::remove(dir / "plan.csv");
  std::string error;
  auto src = ReplaySource::Open(dir.string(), "", &error);
  ASSERT_TRUE(src) << error;
  EXPECT_EQ(src->Hello()["reach"]["note"], "no plan.csv in the run folder (reach --plan-log)");
}
