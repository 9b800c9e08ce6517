// Static load: a rigid block resting on the soft contact settles at the penetration the spring
// law predicts for its weight, delta = (m g / k)^(1/n), within 1 %, landing flat or tilted, on
// a plane (closed form), a box (FCL) and a convex mesh (FCL GJK/EPA).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::BlockModel;
using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kG = 9.81;
constexpr double kMass = 60.0;  // about half of the robot: one foot standing
constexpr double kDt = 0.0005;

struct Case {
  std::string name;
  std::string env;
  std::string assets;
  double exponent;
  double stiffness;
  double tilt_deg;  // initial rotation about the sole's x and y
  std::string integrator = "Euler";
};

class StaticLoad : public ::testing::TestWithParam<Case> {};

TEST_P(StaticLoad, SettlesAtTheSpringLawPenetration) {
  const Case& c = GetParam();
  std::string error;
  ModelPtr m = LoadString(BlockModel(kDt, kMass, c.env, "0 0 -9.81", c.assets, c.integrator), &error);
  ASSERT_TRUE(m) << error;
  DataPtr d(mj_makeData(m.get()));
  SoftContactParams p;
  p.exponent = c.exponent;
  p.stiffness = c.stiffness;
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {}, p, kMass, &error);
  ASSERT_TRUE(contact) << error;

  const double expected = std::pow(kMass * kG / p.stiffness, 1.0 / p.exponent);
  // Start 1 mm above the floor (its lowest point), tilted about x and y.
  const double t = c.tilt_deg * M_PI / 180;
  const Eigen::Quaterniond q = Eigen::AngleAxisd(t, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(t, Eigen::Vector3d::UnitY());
  const Eigen::Matrix3d R = q.toRotationMatrix();
  const Eigen::Vector3d half(0.125, 0.07, 0.01);
  d->qpos[2] = R.row(2).cwiseAbs().dot(half) + 0.001;
  d->qpos[3] = q.w();
  d->qpos[4] = q.x();
  d->qpos[5] = q.y();
  d->qpos[6] = q.z();

  const int steps = static_cast<int>(2.0 / kDt);
  for (int i = 0; i < steps; ++i) {
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
  }
  contact->ApplyBeforeStep(m.get(), d.get());
  const SoleWrench& w = contact->wrenches()[0];
  // Penetration of the bottom face's centre (the block came to rest flat).
  const double sink = -(d->qpos[2] - half.z());
  const Eigen::Quaterniond qe(d->qpos[3], d->qpos[4], d->qpos[5], d->qpos[6]);
  const double tilt = qe.toRotationMatrix().col(2).head<2>().norm();  // sin of the tilt
  std::printf("[%s] sink %.6f mm, expected %.6f mm (error %.4f %%), fitted depth %.6f mm, "
              "normal force %.3f N (m g = %.3f), residual tilt %.2e rad, %d points\n",
              c.name.c_str(), sink * 1e3, expected * 1e3, 100 * (sink - expected) / expected,
              w.depth * 1e3, w.normal_force, kMass * kG, tilt, w.points);
  EXPECT_NEAR(sink, expected, 0.01 * expected);        // the stated 1 %
  EXPECT_NEAR(w.depth, expected, 0.01 * expected);     // the least-squares estimate agrees
  EXPECT_NEAR(w.normal_force, kMass * kG, 0.01 * kMass * kG);
  EXPECT_LT(tilt, 1e-3);                               // came to rest flat
  EXPECT_EQ(w.points, p.grid_x * p.grid_y);
  EXPECT_LT(std::abs(d->qvel[2]), 1e-4);               // at rest
}

INSTANTIATE_TEST_SUITE_P(
    Contact, StaticLoad,
    ::testing::Values(Case{"plane_flat", testing::kPlaneFloor, "", 1.0, 3.0e5, 0.0},
                      Case{"plane_tilted", testing::kPlaneFloor, "", 1.0, 3.0e5, 2.0},
                      Case{"plane_tilted_default_k", testing::kPlaneFloor, "", 1.0, 3.0e6, 2.0},
                      Case{"plane_hertz_tilted", testing::kPlaneFloor, "", 1.5, 6.6e6, 2.0},
                      Case{"box_flat", testing::kBoxFloor, "", 1.0, 3.0e5, 0.0},
                      Case{"box_tilted", testing::kBoxFloor, "", 1.0, 3.0e5, 2.0},
                      Case{"mesh_tilted", testing::kMeshFloor, testing::kMeshAsset, 1.0, 3.0e5,
                           2.0},
                      // The force is held over the step (zero-order hold) for the others too.
                      Case{"plane_tilted_rk4", testing::kPlaneFloor, "", 1.0, 3.0e5, 2.0, "RK4"},
                      Case{"plane_tilted_implicit", testing::kPlaneFloor, "", 1.0, 3.0e5, 2.0,
                           "implicit"}),
    [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

}  // namespace
}  // namespace ohrp::contact
