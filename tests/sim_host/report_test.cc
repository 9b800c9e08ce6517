// The soles' rectangles in sim_host's summary (SoleRectangles, sim_host/report.h) for HRP-1S,
// against the MJCF read by hand: the ankle sensor lfsensor sits at (0, 0, -0.07) of the
// LLEG_ANKLE_R body, the sole box LLEG_SOLE at (0.055, 0, -0.06) with half sizes
// 0.125 x 0.07 x 0.01, both with the body's axes; the foot (LLEG_LINK6) has 1.9 kg at
// (0.08, 0, -0.03). So in the sensor frame x in [-0.07, 0.18], y in [-0.07, 0.07], the bottom
// face at z = 0, and the foot's centre of mass at (0.08, 0, 0.04).
#include <gtest/gtest.h>

#include <string>

#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/report.h"

namespace ohrp::sim {
namespace {

constexpr double kTol = 1e-9;  // [m] a rigid offset: exact up to rounding

TEST(SoleRectangles, Hrp1sSolesInTheirAnkleSensorFrames) {
  std::string error;
  auto scene = model::Scene::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  const auto rects = SoleRectangles(scene->m(), robot);
  ASSERT_EQ(rects.size(), 2u);
  for (const auto& r : rects) {
    const bool left = r.sensor == "lfsensor";
    EXPECT_TRUE(left || r.sensor == "rfsensor") << r.sensor;
    EXPECT_EQ(r.sole, left ? "LLEG_SOLE" : "RLEG_SOLE");
    EXPECT_NEAR(r.x[0], -0.07, kTol);
    EXPECT_NEAR(r.x[1], 0.18, kTol);
    EXPECT_NEAR(r.y[0], -0.07, kTol);
    EXPECT_NEAR(r.y[1], 0.07, kTol);
    EXPECT_NEAR(r.z, 0.0, kTol);
    EXPECT_NEAR(r.foot_mass, 1.9, kTol);
    EXPECT_NEAR(r.foot_com[0], 0.08, kTol);
    EXPECT_NEAR(r.foot_com[1], 0.0, kTol);
    EXPECT_NEAR(r.foot_com[2], 0.04, kTol);
  }
}

}  // namespace
}  // namespace ohrp::sim
