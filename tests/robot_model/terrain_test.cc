// Tests walking/terrain: footsteps on a scene's surfaces against the scenes' closed-form
// geometry (the 5 deg ramps of scene_ramp_updown.xml, the 0.1 m stairs of scene_stairs.xml):
// heights to 1 mm, tilts to 0.1 deg, a sole across a crease resting on the highest points, a
// step moved off a stair's edge, and the errors (no robot, no surface under a sole).
#include "walking/terrain.h"

#include <gtest/gtest.h>

#include <cmath>

namespace ohrp::walking {
namespace {

const std::string kSource = OHRP_SOURCE_DIR;
const Eigen::Vector2d kHalf(0.125, 0.07);  // HRP-1S's sole
const double kSlope = 5.0 * M_PI / 180;

// the midpoint of HRP-1S's soles' bottom centres at the halfsit keyframe, from MuJoCo directly
Eigen::Vector3d SoleMid(const std::string& scene) {
  char error[512] = "";
  mjModel* m = mj_loadXML((kSource + "/mjcf/hrp1s/" + scene).c_str(), nullptr, error, sizeof error);
  EXPECT_TRUE(m) << error;
  if (!m) return Eigen::Vector3d::Zero();
  mjData* d = mj_makeData(m);
  mj_resetDataKeyframe(m, d, mj_name2id(m, mjOBJ_KEY, "halfsit"));
  mj_forward(m, d);
  Eigen::Vector3d mid = Eigen::Vector3d::Zero();
  for (const char* name : {"LLEG_SOLE", "RLEG_SOLE"}) {
    const int g = mj_name2id(m, mjOBJ_GEOM, name);
    for (int k = 0; k < 3; ++k) mid[k] += 0.5 * (d->geom_xpos[3 * g + k] - d->geom_xmat[9 * g + 3 * k + 2] * m->geom_size[3 * g + 2]);
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return mid;
}

std::unique_ptr<TerrainMap> Load(const std::string& scene) {
  std::string error;
  auto t = TerrainMap::Load(kSource + "/mjcf/hrp1s/" + scene, "halfsit", &error);
  EXPECT_TRUE(t) << error;
  return t;
}

TEST(Terrain, StartFrameIsBetweenTheSoles) {
  auto t = Load("scene_flat.xml");
  ASSERT_TRUE(t);
  const Eigen::Vector3d mid = SoleMid("scene_flat.xml");
  EXPECT_NEAR((t->origin() - mid).norm(), 0, 1e-9);
  EXPECT_NEAR(t->origin().y(), 0, 1e-6);
  EXPECT_NEAR(t->origin().z(), 0, 1e-3);  // the soles' bottoms on the floor
  EXPECT_NEAR(t->yaw(), 0, 1e-9);
}

// on the ramp up: z = (x - 0.6) tan 5 deg in the world, pitched 5 deg (toes up: the normal
// leans back, -x), flat across
TEST(Terrain, SolesOnTheSlopeLieOnIt) {
  auto t = Load("scene_ramp_updown.xml");
  ASSERT_TRUE(t);
  const double kOriginX = t->origin().x();
  for (double x_world : {1.0, 1.5, 1.9}) {
    SurfaceSample s;
    std::string why;
    ASSERT_TRUE(t->SurfaceUnder({x_world - kOriginX, 0.1}, 0, kHalf, &s, &why)) << why;
    EXPECT_TRUE(s.planar);
    EXPECT_NEAR(s.z, (x_world - 0.6) * std::tan(kSlope), 1e-3) << x_world;
    EXPECT_NEAR(s.pitch, -kSlope, 0.1 * M_PI / 180);
    EXPECT_NEAR(s.roll, 0, 0.1 * M_PI / 180);
  }
  // on the way down: pitched the other way; the top: flat at H = 1.5 tan 5 deg
  SurfaceSample down, top;
  std::string why;
  ASSERT_TRUE(t->SurfaceUnder({3.8 - kOriginX, 0}, 0, kHalf, &down, &why)) << why;
  EXPECT_NEAR(down.pitch, kSlope, 0.1 * M_PI / 180);
  ASSERT_TRUE(t->SurfaceUnder({2.6 - kOriginX, 0}, 0, kHalf, &top, &why)) << why;
  EXPECT_NEAR(top.z, 1.5 * std::tan(kSlope), 1e-3);
  EXPECT_NEAR(top.pitch, 0, 1e-6);
  // a sole turned 90 deg on the slope: the tilt is about the world's x now (roll), still 5 deg
  SurfaceSample turned;
  ASSERT_TRUE(t->SurfaceUnder({1.5 - kOriginX, 0}, M_PI / 2, kHalf, &turned, &why)) << why;
  EXPECT_NEAR(turned.pitch, -kSlope, 0.1 * M_PI / 180);
  EXPECT_NEAR(turned.roll, 0, 0.1 * M_PI / 180);
}

// across the ramp's foot the sole rests on its heel (floor) and on the ramp under its toes:
// tilted less than the ramp, every sample on or below the sole, not planar
TEST(Terrain, ASoleAcrossACreaseRestsOnTheHighestPoints) {
  auto t = Load("scene_ramp_updown.xml");
  ASSERT_TRUE(t);
  const double kOriginX = t->origin().x();
  SurfaceSample s;
  std::string why;
  ASSERT_TRUE(t->SurfaceUnder({0.65 - kOriginX, 0}, 0, kHalf, &s, &why)) << why;
  EXPECT_FALSE(s.planar);
  EXPECT_LT(s.pitch, 0);
  EXPECT_GT(s.pitch, -kSlope);
  // the toe's sample (0.12 ahead) lies on the ramp: z_toe = z + 0.12 tan(-pitch)
  const double toe = s.z + 0.12 * std::tan(-s.pitch);
  EXPECT_NEAR(toe, (0.65 + 0.12 - 0.6) * std::tan(kSlope), 1e-3);
}

// a step on the second stair (0.2 m); one across the first riser moves onto one stair
TEST(Terrain, StepsOnStairs) {
  auto t = Load("scene_stairs.xml");
  ASSERT_TRUE(t);
  const double kOriginX = t->origin().x();
  std::vector<Footstep> steps(2);
  steps[0].foot = kRight;
  steps[0].p = Eigen::Vector3d(0.95 - kOriginX, -0.09, 0);   // in the middle of stair 2
  steps[1].foot = kLeft;
  steps[1].p = Eigen::Vector3d(0.59 - kOriginX, 0.09, 0);    // its heel 0.035 before the riser at 0.5
  std::string error;
  StepLimits limits;
  limits.sole_half_size = kHalf;
  limits.width = 0.18;
  limits.max_forward = 1.0;  // the steps here are far apart: only the terrain is tested
  limits.max_backward = 1.0;
  FeetPose start;
  start.p[kLeft] = Eigen::Vector3d(0.94 - kOriginX, 0.09, 0.2);
  start.p[kRight] = Eigen::Vector3d(0.5 - kOriginX, -0.09, 0);
  start.yaw[0] = start.yaw[1] = 0;
  ASSERT_TRUE(t->PlaceSteps(&steps, start, limits, 0.05, &error)) << error;
  EXPECT_NEAR(steps[0].p.z(), 0.2, 1e-3);
  EXPECT_NEAR(steps[0].pitch, 0, 1e-6);
  // moved (by the least shift on a 1 cm grid) to rest on one plane: the floor or stair 1
  const double x = steps[1].p.x() + kOriginX;
  const bool on_floor = x + kHalf.x() - 0.005 <= 0.5 + 1e-9 && std::abs(steps[1].p.z()) < 1e-3;
  const bool on_stair = x - kHalf.x() + 0.005 >= 0.5 - 1e-9 && std::abs(steps[1].p.z() - 0.1) < 1e-3;
  EXPECT_TRUE(on_floor || on_stair) << "x " << x << " z " << steps[1].p.z();
  // the nearest spot onto stair 1 is 3 cm ahead (the heel's samples then lie on the riser's
  // edge itself, where a ray may hit either face: 4 cm)
  EXPECT_TRUE(on_stair);
  EXPECT_GE(x, 0.62 - 1e-9);
  EXPECT_LE(x, 0.63 + 1e-9);
}

// a sole across the first riser bears only on the stair: the bearing region is the part of the
// sole past the riser (to 1 cm, the samples' spacing), across the sole's whole width
TEST(Terrain, ASoleAcrossARiserBearsOnTheStairOnly) {
  auto t = Load("scene_stairs.xml");
  ASSERT_TRUE(t);
  const double x_world = 0.55;  // the sole spans 0.425 .. 0.675, the riser at 0.5
  SurfaceSample s;
  std::string why;
  ASSERT_TRUE(t->SurfaceUnder({x_world - t->origin().x(), 0}, 0, kHalf, &s, &why)) << why;
  EXPECT_FALSE(s.planar);
  EXPECT_NEAR(s.z, 0.1, 1e-3);
  EXPECT_NEAR(s.pitch, 0, 1e-6);
  const double lo = x_world + s.contact_centre.x() - s.contact_half.x();
  const double hi = x_world + s.contact_centre.x() + s.contact_half.x();
  EXPECT_NEAR(hi, x_world + kHalf.x(), 1e-9);  // to the toe
  EXPECT_GE(lo, 0.5 - 1e-9);                   // not behind the riser
  EXPECT_LT(lo, 0.5 + 0.07);                   // the samples are 6 cm apart along the sole
  EXPECT_NEAR(s.contact_half.y(), kHalf.y(), 1e-9);
}

TEST(Terrain, Errors) {
  std::string error;
  EXPECT_FALSE(TerrainMap::Load(kSource + "/mjcf/hrp1s/nosuch.xml", "", &error));
  EXPECT_NE(error.find("nosuch.xml"), std::string::npos) << error;
  error.clear();
  EXPECT_FALSE(TerrainMap::Load(kSource + "/mjcf/bench/box_slide.xml", "", &error));
  EXPECT_NE(error.find("soles"), std::string::npos) << error;
  EXPECT_FALSE(TerrainMap::Load(kSource + "/mjcf/hrp1s/scene_flat.xml", "nosuch", &error));
  // the stairs' boxes end 1.2 m to the side: a sole beyond the floor plane's 20 m has nothing
  auto t = Load("scene_flat.xml");
  ASSERT_TRUE(t);
  std::vector<Footstep> steps(1);
  steps[0].p = Eigen::Vector3d(30, 0, 0);
  StepLimits limits;
  FeetPose start;
  start.p[0] = start.p[1] = Eigen::Vector3d::Zero();
  start.yaw[0] = start.yaw[1] = 0;
  EXPECT_FALSE(t->PlaceSteps(&steps, start, limits, 0.05, &error));
  EXPECT_NE(error.find("step 1"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::walking
