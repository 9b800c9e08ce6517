// Heightfields: read as MuJoCo reads them, the smallest penetration of the neighbourhood on a
// ridge and in a valley, and a block resting on a sloped heightfield at the spring law's sink.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "contact/geometry.h"
#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

constexpr double kG = 9.81;

// A 2 x 1.6 m heightfield (21 x 17 samples, 0.1 m of elevation range, 0.05 m base) at
// z = -0.02, planar: z = 0.1 * (0.3 * c/(ncol-1) + 0.2 * r/(nrow-1)).
std::string HeightFieldModel(double dt) {
  return "<mujoco><option timestep=\"" + std::to_string(dt) +
         "\" integrator=\"Euler\"/><asset>"
         "<hfield name=\"terrain\" nrow=\"17\" ncol=\"21\" size=\"1 0.8 0.1 0.05\"/></asset>"
         "<worldbody><geom name=\"ground\" type=\"hfield\" hfield=\"terrain\" pos=\"0 0 -0.02\" "
         "contype=\"1\" conaffinity=\"1\"/>"
         "<body name=\"probe\" pos=\"0 0 1\"><freejoint/>"
         "<geom name=\"ball\" type=\"sphere\" size=\"0.05\" contype=\"1\" conaffinity=\"1\" "
         "mass=\"1\"/></body>"
         "<body name=\"block\" pos=\"0 0 1.5\"><freejoint/>"
         "<inertial pos=\"0 0 0\" mass=\"60\" diaginertia=\"0.1 0.31 0.41\"/>"
         "<geom name=\"sole\" type=\"box\" size=\"0.125 0.07 0.01\" contype=\"0\" "
         "conaffinity=\"0\"/></body></worldbody></mujoco>";
}

void FillPlanar(mjModel* m) {
  const int nrow = m->hfield_nrow[0], ncol = m->hfield_ncol[0];
  for (int r = 0; r < nrow; ++r) {
    for (int c = 0; c < ncol; ++c) {
      m->hfield_data[r * ncol + c] =
          static_cast<float>(0.3 * c / (ncol - 1.0) + 0.2 * r / (nrow - 1.0));
    }
  }
}

TEST(ContactHeightField, ReadAsMuJoCoReadsIt) {
  // MuJoCo's exact ray-heightfield intersection (mj_ray) gives the surface height; ours must
  // put the surface at the same place (layout: rows along y, columns along x, elevation
  // data * size[2], geom frame), with the plane's normal. (MuJoCo's own sphere-heightfield
  // contacts are not an oracle: in 2.2.2 they collide prisms and their depths/normals are off
  // by up to a few mm / 20 deg on this planar field.)
  std::string error;
  ModelPtr m = LoadString(HeightFieldModel(0.001), &error);
  ASSERT_TRUE(m) << error;
  FillPlanar(m.get());
  DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {"ground"}, SoftContactParams{}, 60,
                                         &error);
  ASSERT_TRUE(contact) << error;
  contact->Evaluate(m.get(), d.get());  // poses the environment objects
  const EnvObject& ground = contact->geometry().env()[0];
  const Eigen::Vector3d plane_normal = Eigen::Vector3d(-0.015, -0.0125, 1).normalized();
  int compared = 0;
  for (double x : {-0.93, -0.61, -0.13, 0.23, 0.77}) {  // off the grid lines (mj_ray misses there)
    for (double y : {-0.71, 0.05, 0.45}) {
      const mjtNum pnt[3] = {x, y, 0.5}, vec[3] = {0, 0, -1};
      int geom = -1;
      const double dist = mj_ray(m.get(), d.get(), pnt, vec, nullptr, 1, -1, &geom);
      ASSERT_EQ(geom, 0) << x << " " << y;
      const double z_mj = 0.5 - dist;
      const double z_formula = -0.02 + 0.1 * (0.3 * (x + 1) / 2 + 0.2 * (y + 0.8) / 1.6);
      EXPECT_NEAR(z_mj, z_formula, 1e-6) << "MuJoCo's layout differs from the formula";
      Eigen::Vector3d n;
      const double below = ContactGeometry::SignedDistance(ground, {x, y, z_mj - 1e-3}, &n);
      EXPECT_NEAR(below, -1e-3 * plane_normal.z(), 1e-6) << x << " " << y;
      EXPECT_GT(n.dot(plane_normal), 1 - 1e-9);
      const double above = ContactGeometry::SignedDistance(ground, {x, y, z_mj + 1e-3}, &n);
      EXPECT_NEAR(above, 1e-3 * plane_normal.z(), 1e-6) << x << " " << y;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 15);
}

TEST(ContactHeightField, SmallestPenetrationOnARidgeAndInAValley) {
  // Ridge along y at x = 0: z = 0.1 - 0.5 |x|, sampled every 0.1 m.
  const int n = 11;
  std::vector<double> ridge(n * n), valley(n * n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const double x = -0.5 + 0.1 * c;
      ridge[r * n + c] = 0.1 - 0.5 * std::abs(x);
      valley[r * n + c] = 0.5 * std::abs(x);
    }
  }
  const auto I = Eigen::Isometry3d::Identity();
  const EnvObject hr = EnvObject::HeightField("ridge", I, n, n, 0.5, 0.5, 0.1, ridge);
  const EnvObject hv = EnvObject::HeightField("valley", I, n, n, 0.5, 0.5, 0.1, valley);
  const double s = std::sqrt(1 + 0.25);
  Eigen::Vector3d normal;
  // 1 cm right of the ridge, 2 cm under the surface: the right slope is the nearest exit.
  double sd = ContactGeometry::SignedDistance(hr, Eigen::Vector3d(0.01, 0.02, 0.095 - 0.02),
                                              &normal);
  EXPECT_NEAR(sd, -0.02 / s, 1e-12);
  EXPECT_NEAR(normal.x(), 0.5 / s, 1e-12);
  // In the valley, 1 cm right of its bottom and 2 cm under the right slope: the left slope's
  // plane is nearer (1 cm / s) but leaving through it ends at x = 0.014, on the right side,
  // still inside; the right slope is the reasonable constraint.
  const Eigen::Vector3d p(0.01, 0.02, -0.015);
  sd = ContactGeometry::SignedDistance(hv, p, &normal);
  EXPECT_NEAR(sd, -(0.5 * 0.01 - p.z()) / s, 1e-12);
  EXPECT_NEAR(normal.x(), -0.5 / s, 1e-12);
  // A 45 deg ledge: the top (z = 0.1) ends at x = 0.1, the face goes down to z = 0 at x = 0.2.
  // A point 1 cm under the top and 1 mm before the edge is 0.011/sqrt(2) = 7.8 mm from the
  // face's plane and can leave through it: the face is the smallest penetration, not the top.
  std::vector<double> step(n * n);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) step[r * n + c] = c <= 6 ? 0.1 : 0.0;  // x <= 0.1: high
  }
  const EnvObject hs = EnvObject::HeightField("ledge", I, n, n, 0.5, 0.5, 0.1, step);
  sd = ContactGeometry::SignedDistance(hs, Eigen::Vector3d(0.099, 0.0, 0.09), &normal);
  EXPECT_NEAR(sd, -0.011 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(normal.x(), 1 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(normal.z(), 1 / std::sqrt(2.0), 1e-12);
  // 5 mm before the edge the top is nearer (face: 0.015/sqrt(2) = 10.6 mm > 10 mm).
  sd = ContactGeometry::SignedDistance(hs, Eigen::Vector3d(0.095, 0.0, 0.09), &normal);
  EXPECT_NEAR(sd, -0.01, 1e-12);
  EXPECT_NEAR(normal.z(), 1.0, 1e-12);
  // Above the surface: outside.
  EXPECT_GT(ContactGeometry::SignedDistance(hv, Eigen::Vector3d(0.2, 0, 0.2), &normal), 0);
}

TEST(ContactHeightField, BlockRestsOnASlopedHeightFieldAtTheSpringLawSink) {
  std::string error;
  constexpr double kDt = 0.0005;
  ModelPtr m = LoadString(HeightFieldModel(kDt), &error);
  ASSERT_TRUE(m) << error;
  FillPlanar(m.get());
  m->geom_contype[mj_name2id(m.get(), mjOBJ_GEOM, "ground")] = 0;  // our contact only
  m->geom_conaffinity[mj_name2id(m.get(), mjOBJ_GEOM, "ground")] = 0;
  DataPtr d(mj_makeData(m.get()));
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {"ground"}, SoftContactParams{}, 60,
                                         &error);
  ASSERT_TRUE(contact) << error;
  // The surface: z = -0.02 + 0.015 (x + 1) + 0.0125 (y + 0.8); its normal and tilt.
  const Eigen::Vector3d nrm = Eigen::Vector3d(-0.015, -0.0125, 1).normalized();
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), nrm);
  const Eigen::Vector3d on_surface(0.1, -0.1, -0.02 + 0.015 * 1.1 + 0.0125 * 0.7);
  const Eigen::Vector3d start = on_surface + nrm * (0.01 + 0.0005);
  d->qpos[7] = start.x();
  d->qpos[8] = start.y();
  d->qpos[9] = start.z();
  d->qpos[10] = q.w();
  d->qpos[11] = q.x();
  d->qpos[12] = q.y();
  d->qpos[13] = q.z();
  for (int i = 0; i < static_cast<int>(2.0 / kDt); ++i) {
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
  }
  contact->ApplyBeforeStep(m.get(), d.get());
  const SoleWrench& w = contact->wrenches()[0];
  const Eigen::Vector3d pos(d->qpos[7], d->qpos[8], d->qpos[9]);
  const double sink = -(nrm.dot(pos - on_surface) - 0.01);  // along the normal
  const double expected = 60 * kG * nrm.z() / SoftContactParams{}.stiffness;
  std::printf("sloped heightfield: sink %.5f mm, expected m g cos / k = %.5f mm (error %.4f %%), "
              "normal (%.4f %.4f %.4f), total force z %.3f N, %d points\n",
              sink * 1e3, expected * 1e3, 100 * (sink - expected) / expected, w.normal.x(),
              w.normal.y(), w.normal.z(), w.force.z(), w.points);
  EXPECT_NEAR(sink, expected, 0.01 * expected);
  EXPECT_GT(w.normal.dot(nrm), 1 - 1e-9);
  EXPECT_NEAR(w.force.z(), 60 * kG, 0.01 * 60 * kG);
  EXPECT_LT(std::abs(d->qvel[6]) + std::abs(d->qvel[7]), 1e-5);  // sticks (tan = 0.02 << mu)
}

}  // namespace
}  // namespace ohrp::contact
