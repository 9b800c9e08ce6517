// The obstacle_contacts check (runner/obstacle_checks.h, issue 34 item 3) on a closed form: a
// 0.2 m cube on a free joint slides along x through a static 0.2 m cube at x = 1; the logged
// cycles in contact are those with |x - 1| < 0.2 (the cubes' half sizes summed).
#include "runner/obstacle_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

const char* kScene = R"(<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <geom name="wall" type="box" pos="1 0 0.5" size="0.1 0.1 0.1"/>
    <body name="robot" pos="0 0 0.5"><freejoint/><geom name="hand" type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
</mujoco>)";

// a log of the cube at x = x0 + step * i (y 0, z 0.5, upright); the rows in contact by the
// closed form in `*touching`
std::string Log(double x0, double step, int rows, int* touching) {
  const std::string path = ::testing::TempDir() + "obstacle_log.csv";
  std::ofstream out(path);
  out << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz\n";
  *touching = 0;
  for (int i = 0; i < rows; ++i) {
    const double x = x0 + step * i;
    out << 0.01 * i << "," << x << ",0,0.5,1,0,0,0\n";
    *touching += std::abs(x - 1) < 0.2;
  }
  return path;
}

ohrp::runner::CheckResult Check(const std::string& log_path) {
  const std::string scene = ::testing::TempDir() + "obstacle_scene.xml";
  std::ofstream(scene) << kScene;
  ohrp::datalog::Table log;
  std::string error;
  EXPECT_TRUE(log.Load(log_path, &error)) << error;
  ohrp::runner::CheckSpec spec;
  spec.type = "obstacle_contacts";
  spec.params["max"] = "0";
  return ohrp::runner::ObstacleContacts(spec, log, nlohmann::json{{"scene", scene}});
}

TEST(ObstacleContacts, CountsTheCyclesInContactOfTheClosedForm) {
  int touching = 0;
  const auto r = Check(Log(0.52, 0.05, 11, &touching));  // x 0.52 .. 1.02
  ASSERT_EQ(touching, 5);                              // 0.82, 0.87, 0.92, 0.97, 1.02
  EXPECT_FALSE(r.passed) << r.detail;
  EXPECT_EQ(r.value, touching) << r.detail;
  EXPECT_NE(r.detail.find("first contact hand / wall at 0.060 s"), std::string::npos) << r.detail;
  // the deepest at x = 1.02, an overlap of 0.2 - 0.02 = 180 mm, of which MuJoCo 2.2's box-box
  // function reports half for two aligned boxes (probed at 0.82 ... 1.00: 10, 25, 50, 75,
  // 100 mm for overlaps of 20 ... 200 mm): the depth is MuJoCo's figure, the count exact
  EXPECT_NE(r.detail.find("deepest 90.0 mm (hand / wall at 0.100 s)"), std::string::npos) << r.detail;
}

TEST(ObstacleContacts, PassesWhenTheCubeStaysApartAndIgnoresTheFloor) {
  int touching = 0;
  const auto r = Check(Log(0.0, 0.05, 10, &touching));  // x 0 .. 0.45, on the floor's plane level
  ASSERT_EQ(touching, 0);
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NE(r.detail.find("(1 static obstacles)"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("in contact: none"), std::string::npos) << r.detail;
}

}  // namespace

// obstacle_clearance (runner/obstacle_checks.h) on closed forms: a ball and a capsule on free
// joints approach a static 0.2 m cube whose near face is at x = 0.9
namespace {

const char* kClearanceScene = R"(<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <geom name="wall" type="box" pos="1 0 0.5" size="0.1 0.1 0.1"/>
    <body name="robot" pos="0 0 0.5"><freejoint/>
      <geom name="ball" type="sphere" size="0.1"/>
      <geom name="stick" type="capsule" pos="0 0 0.5" size="0.02 0.1"/>
    </body>
  </worldbody>
</mujoco>)";

// a log of the base at x = x0 + step * i, turned by `pitch` [rad] about y
std::string PoseLog(double x0, double step, int rows, double pitch) {
  const std::string path = ::testing::TempDir() + "clearance_log.csv";
  std::ofstream out(path);
  out << "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz\n";
  for (int i = 0; i < rows; ++i)
    out << 0.01 * i << "," << x0 + step * i << ",0,0.5," << std::cos(pitch / 2) << ",0,"
        << std::sin(pitch / 2) << ",0\n";
  return path;
}

ohrp::runner::CheckResult Clearance(const std::string& log_path, double min) {
  const std::string scene = ::testing::TempDir() + "clearance_scene.xml";
  std::ofstream(scene) << kClearanceScene;
  ohrp::datalog::Table log;
  std::string error;
  EXPECT_TRUE(log.Load(log_path, &error)) << error;
  ohrp::runner::CheckSpec spec;
  spec.type = "obstacle_clearance";
  spec.params["min"] = std::to_string(min);
  return ohrp::runner::ObstacleClearance(spec, log, nlohmann::json{{"scene", scene}});
}

}  // namespace

// upright, the stick (0.5 m above the ball) is at the wall's height minus 0.5 m: out of reach;
// the ball's gap is 0.9 - x - 0.1, smallest at the last row x = 0.55: 250 mm
TEST(ObstacleClearance, TheBallsGapIsTheClosedForm) {
  const auto r = Clearance(PoseLog(0.1, 0.05, 10, 0.0), 0.2);
  EXPECT_NEAR(r.value, 0.25, 1e-6) << r.detail;
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NE(r.detail.find("closest ball / wall at 250.0 mm (0.090 s)"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("0 of 10 logged cycles closer than 200.0 mm"), std::string::npos) << r.detail;
}

// turned 90 deg about y the stick lies along +x at the ball's height: its far end at
// x + 0.5 + 0.1 and its radius 0.02 make a gap of 0.9 - x - 0.62 = 0.28 - x, below the ball's;
// from x = 0.1 by 0.05: 180, 130, 80, 30 mm, then -20 mm (the stick 20 mm inside the wall)
TEST(ObstacleClearance, ATurnedCapsulesGapAndOverlapAreTheClosedForm) {
  const auto r = Clearance(PoseLog(0.1, 0.05, 5, M_PI / 2), 0.05);
  EXPECT_NEAR(r.value, -0.02, 1e-6) << r.detail;
  EXPECT_FALSE(r.passed) << r.detail;
  EXPECT_NE(r.detail.find("closest stick / wall at -20.0 mm (0.040 s)"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("2 of 5 logged cycles closer than 50.0 mm"), std::string::npos) << r.detail;
}

// far away the closest pair is still measured: the ball at x = -3 is 3.8 m from the wall
TEST(ObstacleClearance, FarFromEveryObstacleTheGapIsStillMeasured) {
  const auto r = Clearance(PoseLog(-3.0, 0.0, 4, 0.0), 0.01);
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 3.8, 1e-6) << r.detail;
  EXPECT_NE(r.detail.find("closest ball / wall at 3800.0 mm (0.000 s)"), std::string::npos) << r.detail;
}
