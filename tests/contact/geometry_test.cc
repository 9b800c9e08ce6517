// Geometry: the cheap bound keeps FCL away from a far sole (queries counted), the closed-form
// per-point constraints agree with FCL's signed distance where FCL is reliable, the smallest
// penetration of a point's neighbourhood is chosen, and the wrench lands in xfrc_applied where
// the force sensors see it.
#include <gtest/gtest.h>

#include <fcl/fcl.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <string>

#include "contact/geometry.h"
#include "contact/soft_contact.h"
#include "contact_test_util.h"

namespace ohrp::contact {
namespace {

using testing::BlockModel;
using testing::DataPtr;
using testing::LoadString;
using testing::ModelPtr;

struct Rig {
  ModelPtr m;
  DataPtr d;
  std::unique_ptr<SoftFootContact> contact;
};

Rig MakeRig(const std::string& env, const std::string& assets = "") {
  Rig r;
  std::string error;
  r.m = LoadString(BlockModel(0.001, 60, env, "0 0 -9.81", assets), &error);
  EXPECT_TRUE(r.m) << error;
  r.d.reset(mj_makeData(r.m.get()));
  r.contact = SoftFootContact::Create(r.m.get(), {"sole"}, {}, SoftContactParams{}, 60, &error);
  EXPECT_TRUE(r.contact) << error;
  return r;
}

// Evaluates the contact with the block's bottom face at `gap` above z = 0, n times.
void EvaluateAt(Rig* r, double gap, int n) {
  r->d->qpos[2] = testing::kSoleHalf[2] + gap;
  for (int i = 0; i < n; ++i) {
    r->contact->ApplyBeforeStep(r->m.get(), r->d.get());
    r->contact->Commit();
  }
}

TEST(ContactGeometry, FarSoleCostsNoFclQuery) {
  Rig r = MakeRig(testing::kBoxFloor);
  EvaluateAt(&r, 1.0, 100);  // 1 m above the box
  EXPECT_EQ(r.contact->stats().fcl_queries, 0);
  EXPECT_EQ(r.contact->stats().pairs_bound, 100);
  EXPECT_FALSE(r.contact->wrenches()[0].in_contact);
  for (int k = 0; k < 6; ++k) EXPECT_EQ(r.d->xfrc_applied[6 + k], 0.0);

  // Within the 10 mm margin but not touching: one sole-vs-box FCL distance per evaluation,
  // which rejects the pair, and no points.
  r.contact->geometry().ResetStats();
  EvaluateAt(&r, 0.005, 10);
  EXPECT_EQ(r.contact->stats().fcl_queries, 10);
  EXPECT_EQ(r.contact->stats().pairs_fcl_far, 10);
  EXPECT_FALSE(r.contact->wrenches()[0].in_contact);

  // Touching: still one FCL query per evaluation, then the 15 points in closed form.
  r.contact->geometry().ResetStats();
  EvaluateAt(&r, -0.001, 10);
  EXPECT_EQ(r.contact->stats().fcl_queries, 10);
  EXPECT_EQ(r.contact->stats().pairs_sampled, 10);
  EXPECT_EQ(r.contact->wrenches()[0].points, 15);
  EXPECT_NEAR(r.contact->wrenches()[0].depth, 0.001, 1e-9);

  // A plane never calls FCL, near or far.
  Rig p = MakeRig(testing::kPlaneFloor);
  EvaluateAt(&p, 1.0, 10);
  EvaluateAt(&p, -0.001, 10);
  EXPECT_EQ(p.contact->stats().fcl_queries, 0);
  EXPECT_EQ(p.contact->stats().pairs_bound, 10);
}

TEST(ContactGeometry, ClosedFormDepthAgreesWithFclSignedDistance) {
  // A rotated, translated box: FCL's sphere-box signed distance (probe radius r: sd = dist + r)
  // against the closed form, for random points inside and outside.
  const Eigen::Vector3d half(0.4, 0.25, 0.1);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.5, -0.2, 0.05);
  const EnvObject box = EnvObject::Box("b", pose, half);
  const double r = 1e-3;
  auto probe = std::make_shared<fcl::Sphered>(r);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  int inside = 0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d local(u(rng) * half.x(), u(rng) * half.y(), u(rng) * half.z());
    const Eigen::Vector3d p = pose * local;
    Eigen::Vector3d n;
    const double sd = ContactGeometry::SignedDistance(box, p, &n);
    fcl::DistanceRequestd req(true, true);
    fcl::DistanceResultd res;
    fcl::Transform3d tp = fcl::Transform3d::Identity();
    tp.translation() = p;
    fcl::distance(probe.get(), tp, box.shape.get(), fcl::Transform3d(pose.matrix()), req, res);
    const double sd_fcl = res.min_distance + r;
    if (sd < -2 * r) {  // inside: exact depth and the nearest face's normal
      ++inside;
      EXPECT_NEAR(sd, sd_fcl, 1e-6) << "point " << p.transpose();
      const Eigen::Vector3d n_fcl = (res.nearest_points[1] - res.nearest_points[0]).normalized();
      EXPECT_GT(n.dot(n_fcl), 1 - 1e-6) << "point " << p.transpose();
    } else if (sd > 0) {
      EXPECT_GT(sd_fcl, 0);  // outside: the sign is what counts (a lower bound)
      EXPECT_LE(sd, sd_fcl + 1e-9);
    }
  }
  EXPECT_GT(inside, 50);
}

TEST(ContactGeometry, ConvexMeshMatchesTheBoxItIsMadeOf) {
  const Eigen::Vector3d half(1, 1, 0.05);
  std::vector<Eigen::Vector3d> v;
  for (int i = 0; i < 8; ++i) {
    v.emplace_back(i & 1 ? half.x() : -half.x(), i & 2 ? half.y() : -half.y(),
                   i & 4 ? half.z() : -half.z());
  }
  // 12 triangles of the box (orientation is fixed by the library).
  const std::vector<int> tris = {0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1,
                                 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3};
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const EnvObject mesh = EnvObject::Convex("m", pose, v, tris);
  const EnvObject box = EnvObject::Box("b", pose, half);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p = pose * Eigen::Vector3d(u(rng) * half.x(), u(rng) * half.y(),
                                                     u(rng) * half.z());
    Eigen::Vector3d n1, n2;
    const double a = ContactGeometry::SignedDistance(mesh, p, &n1);
    const double b = ContactGeometry::SignedDistance(box, p, &n2);
    EXPECT_NEAR(a, b, 1e-12);
    EXPECT_GT(n1.dot(n2), 1 - 1e-9);
  }
}

TEST(ContactGeometry, EachPointTakesTheSmallestPenetrationOfItsNeighbourhood) {
  // A 2 cm step (a box on the floor plane, its edge across the sole at x = 0.025), the sole
  // 1 mm into the step's top: the points over the step are pushed up by 1 mm (not out of the
  // step's side, which is farther), the points beyond the edge are not in contact (the floor
  // is 2 cm lower).
  ContactGeometry g({EnvObject::Plane("floor", Eigen::Isometry3d::Identity()),
                     EnvObject::Box("step", Eigen::Isometry3d(Eigen::Translation3d(-0.475, 0, 0.01)),
                                    Eigen::Vector3d(0.5, 0.5, 0.01))},
                    0.01);
  SoleBox sole;
  sole.half = Eigen::Vector3d(0.125, 0.07, 0.01);
  sole.pose = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.02 + 0.01 - 0.001));
  const auto grid = MakeGrid(sole.half, 5, 3);
  std::vector<PointContact> pts;
  g.Find(sole, grid, &pts);
  int over_step = 0;
  for (const SamplePoint& s : grid) over_step += s.u < 0.025 ? 1 : 0;
  ASSERT_EQ(static_cast<int>(pts.size()), over_step);
  for (const PointContact& c : pts) {
    EXPECT_EQ(c.object, 1);
    EXPECT_NEAR(c.depth, 0.001, 1e-12);
    EXPECT_NEAR(c.normal.z(), 1.0, 1e-12);
  }
  // A wall (a tall box) whose face is 5 mm inside the last column of points, whose bottom is
  // 19 mm below them: the side face is the nearest one, the push is sideways.
  // (the last column lies on the sole's edge, x = 0.125: the face at x = 0.12)
  ContactGeometry wall({EnvObject::Box("wall", Eigen::Isometry3d(Eigen::Translation3d(0.62, 0, 0.5)),
                                       Eigen::Vector3d(0.5, 0.5, 0.5))},
                       0.01);
  wall.Find(sole, grid, &pts);
  ASSERT_FALSE(pts.empty());
  for (const PointContact& c : pts) {
    EXPECT_NEAR(c.normal.x(), -1.0, 1e-12);
    EXPECT_NEAR(c.depth, c.pos.x() - 0.12, 1e-12);
  }
}

TEST(ContactGeometry, WrenchGoesToXfrcAppliedOnceAndCanBeRemoved) {
  Rig r = MakeRig(testing::kPlaneFloor);
  const int body = 1;
  r.d->xfrc_applied[6 * body + 0] = 7.0;  // someone else's push, kept
  r.d->qpos[2] = testing::kSoleHalf[2] - 0.002;
  r.contact->SetImplicit(false);  // the law as evaluated (the implicit step adds its correction)
  for (int i = 0; i < 3; ++i) r.contact->ApplyBeforeStep(r.m.get(), r.d.get());
  const SoleWrench& w = r.contact->wrenches()[0];
  EXPECT_NEAR(w.force.z(), SoftContactParams{}.stiffness * 0.002, 1e-6);
  EXPECT_NEAR(r.d->xfrc_applied[6 * body + 2], w.force.z(), 1e-9);  // added once, not 3 times
  EXPECT_NEAR(r.d->xfrc_applied[6 * body + 0], 7.0, 1e-9);
  // Torque about the centre of mass: the centre of pressure is under it, none.
  for (int k = 3; k < 6; ++k) EXPECT_NEAR(r.d->xfrc_applied[6 * body + k], 0.0, 1e-9);
  r.contact->Remove(r.d.get());
  EXPECT_NEAR(r.d->xfrc_applied[6 * body + 2], 0.0, 1e-9);
  EXPECT_NEAR(r.d->xfrc_applied[6 * body + 0], 7.0, 1e-9);
}

TEST(ContactGeometry, ForceSensorAboveTheSoleSeesTheContact) {
  // A 50 kg "leg" (free) carrying a 10 kg "foot" body welded to it, the sole on the foot and a
  // force sensor on the foot's site: at rest the sensor reads the leg's weight, which only
  // works because the contact wrench is an external body force (xfrc_applied).
  const std::string xml =
      "<mujoco><option timestep=\"0.0005\" integrator=\"Euler\"/>"
      "<default><geom contype=\"0\" conaffinity=\"0\"/></default><worldbody>"
      "<geom name=\"floor\" type=\"plane\" size=\"5 5 0.1\"/>"
      "<body name=\"leg\" pos=\"0 0 0.2\"><freejoint/>"
      "<inertial pos=\"0 0 0\" mass=\"50\" diaginertia=\"1 1 1\"/>"
      "<body name=\"foot\" pos=\"0 0 -0.19\">"
      "<inertial pos=\"0 0 0\" mass=\"10\" diaginertia=\"0.1 0.1 0.1\"/>"
      "<site name=\"ankle\" pos=\"0 0 0\"/>"
      "<geom name=\"sole\" type=\"box\" size=\"0.125 0.07 0.01\"/></body></body></worldbody>"
      "<sensor><force name=\"ankle_force\" site=\"ankle\"/></sensor></mujoco>";
  std::string error;
  ModelPtr m = LoadString(xml, &error);
  ASSERT_TRUE(m) << error;
  DataPtr d(mj_makeData(m.get()));
  auto contact = SoftFootContact::Create(m.get(), {"sole"}, {}, SoftContactParams{}, 60, &error);
  ASSERT_TRUE(contact) << error;
  for (int i = 0; i < 4000; ++i) {
    contact->ApplyBeforeStep(m.get(), d.get());
    mj_step(m.get(), d.get());
    contact->Commit();
  }
  const double fz = d->sensordata[2];  // in the site frame (aligned with the world here)
  std::printf("ankle force sensor z %.3f N, leg weight %.3f N, contact %.3f N\n", fz, 50 * 9.81,
              contact->wrenches()[0].normal_force);
  EXPECT_NEAR(std::abs(fz), 50 * 9.81, 0.01 * 50 * 9.81);
  EXPECT_NEAR(contact->wrenches()[0].normal_force, 60 * 9.81, 0.01 * 60 * 9.81);
}

}  // namespace
}  // namespace ohrp::contact
