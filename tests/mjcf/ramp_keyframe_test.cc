// The keyframe halfsit_ramp of scene_slope.xml by forward kinematics: both soles lie parallel
// to the 5 deg ramp, their bottom faces 0.5 mm above its top face. The ramp is stated here in
// closed form, not read from the XML: top face z(x) = (x - 0.6) tan(5 deg) for x >= 0.6, so its
// upward normal is (-sin a, 0, cos a) and the signed distance of a point p above it is
// -sin a (p_x - 0.6) + cos a p_z.
#include <mujoco/mujoco.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <string>

namespace {

constexpr double kSlope = 5 * M_PI / 180;      // [rad]
constexpr double kRampStartX = 0.6;            // [m] where the ramp meets the floor
constexpr double kGap = 0.0005;                // [m] sole above the ramp in the keyframe
constexpr double kGapTolerance = 0.0005;       // [m] every corner within 1 mm of the ramp, above it
constexpr double kParallelTolerance = 0.01;    // [deg]

void OnMujocoError(const char* msg) {
  std::fprintf(stderr, "MuJoCo error: %s\n", msg);
  std::abort();
}

double AboveRamp(const double p[3]) {
  return -std::sin(kSlope) * (p[0] - kRampStartX) + std::cos(kSlope) * p[2];
}

TEST(RampKeyframe, SolesLieParallelToTheRampJustAboveIt) {
  mju_user_error = OnMujocoError;
  const std::string path = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_slope.xml";
  char err[1024] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  ASSERT_NE(m, nullptr) << err;
  mjData* d = mj_makeData(m);
  const int key = mj_name2id(m, mjOBJ_KEY, "halfsit_ramp");
  ASSERT_GE(key, 0);
  mj_resetDataKeyframe(m, d, key);
  mj_kinematics(m, d);
  const double n_W[3] = {-std::sin(kSlope), 0, std::cos(kSlope)};
  for (const char* name : {"LLEG_SOLE", "RLEG_SOLE"}) {
    const int g = mj_name2id(m, mjOBJ_GEOM, name);
    ASSERT_GE(g, 0) << name;
    const double* p = d->geom_xpos + 3 * g;
    const double* R = d->geom_xmat + 9 * g;  // row-major, column 2 is the sole's z axis
    // the sole's z axis along the ramp's normal
    const double cosang = R[2] * n_W[0] + R[5] * n_W[1] + R[8] * n_W[2];
    EXPECT_LT(std::acos(std::min(1.0, cosang)) * 180 / M_PI, kParallelTolerance) << name;
    // its bottom face's corners just above the ramp, on the ramp's part (x >= 0.6)
    const double* h = m->geom_size + 3 * g;
    for (int c = 0; c < 4; ++c) {
      const double local[3] = {(c & 1 ? 1 : -1) * h[0], (c & 2 ? 1 : -1) * h[1], -h[2]};
      double q[3];
      for (int i = 0; i < 3; ++i)
        q[i] = p[i] + R[3 * i] * local[0] + R[3 * i + 1] * local[1] + R[3 * i + 2] * local[2];
      EXPECT_GT(q[0], kRampStartX) << name << " corner " << c;
      EXPECT_NEAR(AboveRamp(q), kGap, kGapTolerance) << name << " corner " << c;
    }
  }
  mj_deleteData(d);
  mj_deleteModel(m);
}

}  // namespace
