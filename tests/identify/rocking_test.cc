// The linearised rocking model (identify/rocking.h): its inverse gives back the stiffness and
// damping it was evaluated with, HRP-1S's geometry in the rocking posture is what the model
// says (mass, centre of mass above the soles), and the closed form's trends hold (a stiffer
// bed rocks faster; damping raises the damping ratio).
#include <gtest/gtest.h>

#include <cstdio>

#include "identify/rocking.h"
#include "robot_model/model.h"

namespace ohrp::identify {
namespace {

RockingGeometry Hrp1sLeaning() {
  std::string error;
  auto scene = model::Scene::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &error);
  EXPECT_TRUE(scene) << error;
  RockingGeometry g;
  if (!scene) return g;
  // controllers/poses/hrp1s_halfsit_lean.yaml's legs
  const std::vector<std::pair<std::string, double>> q = {
      {"RLEG_HIP_P", -0.349066}, {"RLEG_KNEE", 0.698132}, {"RLEG_ANKLE_P", -0.409066},
      {"LLEG_HIP_P", -0.349066}, {"LLEG_KNEE", 0.698132}, {"LLEG_ANKLE_P", -0.409066}};
  EXPECT_TRUE(GeometryAt(scene->m(), q, contact::SoftContactParams{}, &g, &error)) << error;
  return g;
}

TEST(Rocking, GeometryOfHrp1sLeaning) {
  const RockingGeometry g = Hrp1sLeaning();
  EXPECT_NEAR(g.mass, 130.8, 0.1);  // mjcf/hrp1s/README.md
  EXPECT_EQ(g.points.size(), 2u * 5 * 3);  // two soles, the default 5 x 3 grid
  EXPECT_GT(g.com_height, 0.6);
  EXPECT_LT(g.com_height, 0.9);
  // leaned forward 0.06 rad at the ankles: the centre of mass over the soles' middle third
  EXPECT_LT(std::fabs(g.com_ahead), 0.04);
  EXPECT_GT(g.Iyy, 5.0);
  std::printf("[ figures  ] HRP-1S leaning: %.2f kg, Iyy %.3f kg m^2, CoM %.4f m above the soles, "
              "%.4f m ahead of their middle\n", g.mass, g.Iyy, g.com_height, g.com_ahead);
}

TEST(Rocking, TheInverseGivesBackStiffnessAndDamping) {
  const RockingGeometry g = Hrp1sLeaning();
  contact::SoftContactParams p;
  for (const auto& [k, d] : std::vector<std::pair<double, double>>{{2e6, 45}, {3e6, 30}, {5e6, 80}}) {
    p.stiffness = k;
    p.damping = d;
    const Mode m = PredictRocking(g.points, g.weights, g.mass, g.Iyy, g.g, p);
    ASSERT_GT(m.omega_d, 0);
    double k2 = 0, d2 = 0;
    std::string error;
    ASSERT_TRUE(InvertRocking(g, p, m.omega_d, m.zeta, &k2, &d2, &error)) << error;
    EXPECT_NEAR(k2, k, 1e-6 * k);
    EXPECT_NEAR(d2, d, 1e-5 * d);
    std::printf("[ figures  ] K %.3g N/m, D %.3g s/m: rocking %.4f Hz, zeta %.4f; inverse %.6g, %.6g\n",
                k, d, m.omega_d / (2 * M_PI), m.zeta, k2, d2);
  }
  // stiffer rocks faster, more damping damps more
  p.stiffness = 2e6;
  p.damping = 45;
  const Mode a = PredictRocking(g.points, g.weights, g.mass, g.Iyy, g.g, p);
  p.stiffness = 2.2e6;
  EXPECT_GT(PredictRocking(g.points, g.weights, g.mass, g.Iyy, g.g, p).omega_d, a.omega_d);
  p.stiffness = 2e6;
  p.damping = 50;
  EXPECT_GT(PredictRocking(g.points, g.weights, g.mass, g.Iyy, g.g, p).zeta, a.zeta);
}

TEST(Rocking, ATargetOutsideTheRangeIsRefusedSayingWhy) {
  const RockingGeometry g = Hrp1sLeaning();
  double k = 0, d = 0;
  std::string error;
  EXPECT_FALSE(InvertRocking(g, contact::SoftContactParams{}, 2 * M_PI * 500, 0.05, &k, &d, &error));
  EXPECT_NE(error.find("outside"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::identify
