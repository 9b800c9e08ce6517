// sim_host's fall watch in-process (sim_host/fall.h): the lowest points of geoms against closed
// forms, HRP-1S lowered into the floor (the first non-foot geom in the ground, its depth to the
// millimetre's closed form), and the cost of one check on the rough floor's 1248 pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "common/scratch.h"
#include "sim_host/fall.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {
namespace {

std::unique_ptr<model::Scene> LoadScene(const std::string& file) {
  model::InstallMujocoHandlers(nullptr);
  std::string error;
  auto scene = model::Scene::Load(std::string(OHRP_SOURCE_DIR) + "/" + file, &error);
  EXPECT_TRUE(scene) << error;
  return scene;
}

TEST(FallWatch, LowestPointsOfPrimitivesAreExact) {
  // each geom turned 0.3 rad about x then placed at z = 1
  const char* xml = R"(<mujoco><compiler angle="radian"/><worldbody>
    <geom name="s" type="sphere" size="0.1" pos="0 0 1"/>
    <geom name="c" type="capsule" size="0.1 0.2" pos="0 0 1" euler="0.3 0 0"/>
    <geom name="y" type="cylinder" size="0.1 0.2" pos="0 0 1" euler="0.3 0 0"/>
    <geom name="b" type="box" size="0.1 0.2 0.3" pos="0 0 1" euler="0.3 0 0"/>
    <geom name="e" type="ellipsoid" size="0.1 0.2 0.3" pos="0 0 1" euler="0.3 0 0"/>
  </worldbody></mujoco>)";
  char err[256] = "";
  const std::string file = ohrp::testing::ScratchFile("geoms", xml, ".xml");
  mjModel* m = mj_loadXML(file.c_str(), nullptr, err, sizeof(err));
  ASSERT_TRUE(m) << err;
  mjData* d = mj_makeData(m);
  mj_kinematics(m, d);
  const double c = std::cos(0.3), s = std::sin(0.3);
  EXPECT_NEAR(GeomLowestPoint(m, d, 0), 0.9, 1e-12);
  EXPECT_NEAR(GeomLowestPoint(m, d, 1), 1 - 0.2 * c - 0.1, 1e-12);
  EXPECT_NEAR(GeomLowestPoint(m, d, 2), 1 - 0.2 * c - 0.1 * s, 1e-12);
  EXPECT_NEAR(GeomLowestPoint(m, d, 3), 1 - 0.2 * s - 0.3 * c, 1e-12);
  EXPECT_NEAR(GeomLowestPoint(m, d, 4), 1 - std::hypot(0.2 * s, 0.3 * c), 1e-12);
  mj_deleteData(d);
  mj_deleteModel(m);
}

// HRP-1S in its model pose (straight legs, soles flat on the floor) lowered by 0.1 m: the first
// of its links in the floor is an ankle's pitch cylinder (radius 0.05, axis horizontal, its
// centre 0.07 m above the sole's bottom), 0.1 - 0.02 = 0.08 m deep; the feet's own geoms and the
// soles do not count
TEST(FallWatch, HrpLoweredIntoTheFloorTouchesWithItsAnkles) {
  auto scene = LoadScene("mjcf/hrp1s/scene_flat.xml");
  mjModel* m = scene->m();
  mjData* d = scene->d();
  model::RobotMap robot;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  ASSERT_TRUE(scene->Reset("", &error)) << error;
  auto watch = FallWatch::Create(m, d, robot, {}, {}, &error);
  ASSERT_TRUE(watch) << error;
  ASSERT_TRUE(watch->on()) << watch->Describe();
  EXPECT_NEAR(watch->start_height(), 0.7235, 1e-9);  // WAIST at 0.7235, soles' bottoms at 0
  mj_kinematics(m, d);
  EXPECT_FALSE(watch->Check(m, d, 0, 0)) << watch->fall().cause;  // standing
  d->qpos[robot.base_qpos + 2] -= 0.1;
  mj_kinematics(m, d);
  ASSERT_TRUE(watch->Check(m, d, 0.5, 100));
  const FallRecord& f = watch->fall();
  EXPECT_EQ(f.kind, FallKind::kContact);
  const std::string body = mj_id2name(m, mjOBJ_BODY, f.body);
  EXPECT_TRUE(body == "LLEG_ANKLE_P" || body == "RLEG_ANKLE_P") << f.cause;
  EXPECT_NEAR(f.depth, 0.08, 1e-6) << f.cause;
  EXPECT_EQ(f.time, 0.5);
  EXPECT_EQ(f.cycle, 100u);
  EXPECT_FALSE(watch->Check(m, d, 0.6, 101));  // the first fall only
}

// the cost of one check of HRP-1S standing on the rough floor (48 robot geoms x 26 ground
// geoms): a figure, bounded loosely (a loaded 2-core machine)
TEST(FallWatch, OneCheckOnTheRoughFloorIsCheap) {
  auto scene = LoadScene("mjcf/hrp1s/scene_rough.xml");
  mjModel* m = scene->m();
  mjData* d = scene->d();
  model::RobotMap robot;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  ASSERT_TRUE(scene->Reset("halfsit", &error)) << error;
  auto watch = FallWatch::Create(m, d, robot, {}, {}, &error);
  ASSERT_TRUE(watch) << error;
  mj_kinematics(m, d);
  std::vector<double> us;
  for (int round = 0; round < 21; ++round) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < 200; ++k) ASSERT_FALSE(watch->Check(m, d, 0, k)) << watch->fall().cause;
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / 200);
  }
  std::nth_element(us.begin(), us.begin() + 10, us.end());
  std::printf("[ figures  ] one fall check, HRP-1S on scene_rough (%zu pairs): median %.2f us\n",
              watch->pairs(), us[10]);
  EXPECT_EQ(watch->pairs(), 48u * 26u);
  EXPECT_LT(us[10], 100.0);
}

}  // namespace
}  // namespace ohrp::sim
