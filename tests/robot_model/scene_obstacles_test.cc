// model::ReadSceneObstacles (issue 34 item 3): a scene's static geoms as the planner's boxes,
// placed in a base frame, against closed forms.
#include "robot_model/scene_obstacles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

using ohrp::model::SceneObstacles;

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

// a floor, a box turned 90 deg about z at (1, 2, 0.5), a capsule in a static body, a free body
const char* kScene = R"(<mujoco>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <geom name="crate" type="box" pos="1 2 0.5" euler="0 0 90" size="0.1 0.2 0.3"/>
    <body name="post" pos="0 -1 0">
      <geom name="pole" type="capsule" pos="0 0 1" size="0.05 0.4"/>
    </body>
    <body name="ball" pos="3 0 1"><freejoint/><geom type="sphere" size="0.1"/></body>
  </worldbody>
</mujoco>)";

TEST(SceneObstacles, StaticGeomsOnlyWithTheirWorldPoses) {
  SceneObstacles s;
  std::string error;
  ASSERT_TRUE(ohrp::model::ReadSceneObstacles(WriteTemp("scene.xml", kScene), &s, &error)) << error;
  ASSERT_EQ(s.boxes.size(), 2u);  // not the floor, not the free ball
  EXPECT_EQ(s.boxes[0].name, "crate");
  EXPECT_EQ(s.boxes[0].shape, "box");
  EXPECT_TRUE(s.boxes[0].half_size.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  EXPECT_TRUE(s.boxes[0].X_WO.translation().isApprox(Eigen::Vector3d(1, 2, 0.5)));
  // 90 deg about z: the box's x axis along the world's y
  EXPECT_NEAR((s.boxes[0].X_WO.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0, 1e-9);
  // a capsule: its bounding box (radius, radius, half length + radius), in the static body
  EXPECT_EQ(s.boxes[1].name, "pole");
  EXPECT_TRUE(s.boxes[1].half_size.isApprox(Eigen::Vector3d(0.05, 0.05, 0.45)));
  EXPECT_TRUE(s.boxes[1].X_WO.translation().isApprox(Eigen::Vector3d(0, -1, 1)));
}

TEST(SceneObstacles, BoxInTheBaseFrameIsTheClosedFormTransform) {
  SceneObstacles s;
  std::string error;
  ASSERT_TRUE(ohrp::model::ReadSceneObstacles(WriteTemp("scene2.xml", kScene), &s, &error)) << error;
  // a base at (0.1, -0.2, 0.7), turned by yaw 30 deg and pitched 5 deg
  const double yaw = M_PI / 6, pitch = 5 * M_PI / 180;
  Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
  X_WB.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY())).toRotationMatrix();
  X_WB.translation() = Eigen::Vector3d(0.1, -0.2, 0.7);
  const Eigen::Isometry3d X_BO = ohrp::model::BoxInFrame(s.boxes[0], X_WB);
  // closed form: p_B = Ry(-pitch) Rz(-yaw) (p_W - p_WB)
  const Eigen::Vector3d d(1 - 0.1, 2 + 0.2, 0.5 - 0.7);
  const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
  const Eigen::Vector3d r(cy * d.x() + sy * d.y(), -sy * d.x() + cy * d.y(), d.z());  // Rz(-yaw)
  const Eigen::Vector3d p(cp * r.x() - sp * r.z(), r.y(), sp * r.x() + cp * r.z());   // Ry(-pitch)
  EXPECT_NEAR((X_BO.translation() - p).norm(), 0, 1e-12);
  // the box's x axis (world y) seen from the base
  const Eigen::Vector3d ry(sy, cy, 0);
  const Eigen::Vector3d x_B(cp * ry.x() - sp * ry.z(), ry.y(), sp * ry.x() + cp * ry.z());
  EXPECT_NEAR((X_BO.linear() * Eigen::Vector3d::UnitX() - x_B).norm(), 0, 1e-9);
}

TEST(SceneObstacles, BadFileAndEmptySceneRefused) {
  SceneObstacles s;
  std::string error;
  EXPECT_FALSE(ohrp::model::ReadSceneObstacles(WriteTemp("bad.xml", "<mujoco><worldbody>"), &s, &error));
  EXPECT_NE(error.find("--scene: "), std::string::npos) << error;
  error.clear();
  const std::string flat = WriteTemp("flat.xml",
      "<mujoco><worldbody><geom type=\"plane\" size=\"1 1 0.1\"/></worldbody></mujoco>");
  EXPECT_FALSE(ohrp::model::ReadSceneObstacles(flat, &s, &error));
  EXPECT_NE(error.find("has no static obstacle"), std::string::npos) << error;
}

TEST(SceneObstacles, TheTableAndShelfScene) {
  SceneObstacles s;
  std::string error;
  ASSERT_TRUE(ohrp::model::ReadSceneObstacles(
      std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_table_shelf.xml", &s, &error)) << error;
  EXPECT_EQ(s.boxes.size(), 12u);  // table top, 4 legs, the box, the shelf's back, 2 sides, 3 boards
  for (const auto& b : s.boxes) EXPECT_EQ(b.name.rfind("LARM", 0), std::string::npos);  // no robot link
}

}  // namespace
