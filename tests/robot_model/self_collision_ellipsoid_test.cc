// Ellipsoids in the self-collision checker (Cassie's pelvis): distances against closed forms.
// A convex set's closest point to a point on the outward normal of a surface point is that
// surface point, and two convex sets whose surface points have opposite normals along the line
// joining them are exactly that far apart (the planes through them separate the sets). So, for
// an ellipsoid with semi-axes h, the surface point with outward normal n (in its frame) is
// diag(h)^2 n / |diag(h) n|, and a second shape touching the plane through it at a gap t is at
// distance t: along the axes (the vertices) and in random directions.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "collision/from_mjcf.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "common/scratch.h"
#include "robot_model/model.h"
#include "test_models.h"

namespace ohrp::collision {
namespace {

constexpr double kTol = 1e-5;  // [m] GJK on curved shapes, certified to 1 um by its lower bound

Shape MakeShape(ShapeType type, const Eigen::Vector3d& size) {
  Shape s;
  s.type = type;
  s.size = size;
  return s;
}

// two welded links (both roots): `a` at the origin unturned, `b` at pose X_b
RobotGeometry TwoShapes(const Shape& a, const Shape& b, const Eigen::Isometry3d& X_b) {
  RobotGeometry g;
  g.name = "two";
  Link la, lb;
  la.name = "a";
  la.shapes = {a};
  lb.name = "b";
  lb.p_PL = X_b.translation();
  lb.q_PL = Eigen::Quaterniond(X_b.linear());
  lb.shapes = {b};
  g.links = {la, lb};
  return g;
}

double DistanceOf(const Shape& a, const Shape& b, const Eigen::Isometry3d& X_b) {
  std::string error;
  auto c = SelfCollision::Create(TwoShapes(a, b, X_b), &error);
  EXPECT_TRUE(c) << error;
  return c ? c->Distance(0, 1, 10.0) : NAN;
}

// the surface point of an ellipsoid (semi-axes h, in its frame) whose outward normal is n
Eigen::Vector3d SurfacePoint(const Eigen::Vector3d& h, const Eigen::Vector3d& n) {
  const Eigen::Vector3d h2 = h.cwiseProduct(h);
  return h2.cwiseProduct(n) / h.cwiseProduct(n).norm();
}

Eigen::Quaterniond RandomTurn(std::mt19937& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized();
}

const Eigen::Vector3d kPelvis(0.15, 0.12, 0.13);  // Cassie's pelvis ellipsoid [m]

TEST(SelfCollisionEllipsoid, SphereAlongEachAxisIsTheVertexGap) {
  const Shape e = MakeShape(ShapeType::kEllipsoid, kPelvis);
  const Shape s = MakeShape(ShapeType::kSphere, {0.05, 0, 0});
  for (int axis = 0; axis < 3; ++axis) {
    for (double gap : {0.0005, 0.02, 0.3}) {
      for (double sign : {1.0, -1.0}) {
        Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
        X.translation() = sign * (kPelvis[axis] + 0.05 + gap) * Eigen::Vector3d::Unit(axis);
        EXPECT_NEAR(DistanceOf(e, s, X), gap, kTol) << "axis " << axis << ", gap " << gap;
      }
    }
  }
}

TEST(SelfCollisionEllipsoid, TwoEllipsoidsAlongAxesTurnedAndOverlapping) {
  const Shape e1 = MakeShape(ShapeType::kEllipsoid, kPelvis);
  const Eigen::Vector3d h2(0.05, 0.2, 0.08);
  const Shape e2 = MakeShape(ShapeType::kEllipsoid, h2);
  // e2's axis k along e1's axis i: a turn taking e2's k to the line
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double gap = 0.01 + 0.01 * i + 0.003 * k;
      Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
      X.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::Unit(k),
                                                      Eigen::Vector3d::Unit(i))
                       .toRotationMatrix();
      X.translation() = (kPelvis[i] + h2[k] + gap) * Eigen::Vector3d::Unit(i);
      EXPECT_NEAR(DistanceOf(e1, e2, X), gap, kTol) << "axes " << i << ", " << k;
    }
  }
  // overlapping by 1 cm along their long axes: the depth is the overlap on that axis (the
  // smallest of all directions here: second derivative 2b^2/a - (2a - D) > 0 at the axis)
  const Shape long1 = MakeShape(ShapeType::kEllipsoid, {0.1, 0.05, 0.05});
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(0.19, 0, 0);
  EXPECT_NEAR(DistanceOf(long1, long1, X), -0.01, 1e-9);
}

// random directions: a sphere, a box face and a second ellipsoid placed a gap t beyond the
// surface point with normal n, their own supporting point on the line
TEST(SelfCollisionEllipsoid, ShapesBeyondTheNormalOfARandomSurfacePoint) {
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> gap(0.001, 0.2);
  const Shape e1 = MakeShape(ShapeType::kEllipsoid, kPelvis);
  const Eigen::Vector3d h2(0.04, 0.11, 0.07), half(0.03, 0.05, 0.02);
  const Shape e2 = MakeShape(ShapeType::kEllipsoid, h2);
  const Shape sphere = MakeShape(ShapeType::kSphere, {0.03, 0, 0});
  const Shape box = MakeShape(ShapeType::kBox, half);
  double worst = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d n = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double t = gap(rng);
    const Eigen::Vector3d v = SurfacePoint(kPelvis, n);
    // the sphere: its centre on the normal
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.translation() = v + (t + 0.03) * n;
    const double ds = DistanceOf(e1, sphere, X) - t;
    // the box: its -z face through v + t n, facing -n (the face's centre on the normal)
    X.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n).toRotationMatrix();
    X.translation() = v + (t + half.z()) * n;
    const double db = DistanceOf(e1, box, X) - t;
    // the second ellipsoid, turned at random: its surface point with normal -n on the line
    const Eigen::Quaterniond R = RandomTurn(rng);
    const Eigen::Vector3d w = R * SurfacePoint(h2, R.inverse() * (-n));
    X.linear() = R.toRotationMatrix();
    X.translation() = v + t * n - w;
    const double de = DistanceOf(e1, e2, X) - t;
    EXPECT_NEAR(ds, 0, kTol) << "trial " << trial;
    EXPECT_NEAR(db, 0, kTol) << "trial " << trial;
    EXPECT_NEAR(de, 0, kTol) << "trial " << trial;
    worst = std::max({worst, std::abs(ds), std::abs(db), std::abs(de)});
  }
  RecordProperty("worst_error_m", std::to_string(worst));
}

// an ellipsoid with equal semi-axes is a sphere: the same distances (and depths) against every
// kind of shape in random poses, apart and overlapping
TEST(SelfCollisionEllipsoid, EqualSemiAxesAreTheSphere) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  const Shape round = MakeShape(ShapeType::kEllipsoid, Eigen::Vector3d::Constant(0.07));
  const Shape sphere = MakeShape(ShapeType::kSphere, {0.07, 0, 0});
  const Shape others[] = {MakeShape(ShapeType::kBox, {0.05, 0.1, 0.03}),
                          MakeShape(ShapeType::kCapsule, {0.04, 0.1, 0}),
                          MakeShape(ShapeType::kCylinder, {0.05, 0.08, 0}),
                          MakeShape(ShapeType::kSphere, {0.06, 0, 0}),
                          MakeShape(ShapeType::kEllipsoid, {0.03, 0.09, 0.05})};
  int overlapping = 0;
  for (int trial = 0; trial < 100; ++trial) {
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = RandomTurn(rng).toRotationMatrix();
    X.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng));
    for (const Shape& o : others) {
      const double want = DistanceOf(sphere, o, X);
      EXPECT_NEAR(DistanceOf(round, o, X), want, kTol)
          << ShapeName(o.type) << ", trial " << trial;
      overlapping += want < 0;
    }
  }
  EXPECT_GT(overlapping, 20);  // depths compared too, not only gaps
}

TEST(SelfCollisionEllipsoid, FromMjcfAndThroughTheFile) {
  constexpr char kXml[] = R"(<mujoco model="egg">
  <worldbody>
    <body name="base"><freejoint/>
      <geom type="ellipsoid" size=".15 .12 .13" pos=".03 0 .03"/>
      <body name="arm" pos=".03 .3 .03">
        <joint name="j" axis="1 0 0" limited="true" range="-1 1"/>
        <geom type="sphere" size=".05"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j"/></actuator>
</mujoco>)";
  std::string error;
  mjModel* m = model::testing::LoadString(kXml, &error);
  ASSERT_TRUE(m) << error;
  model::RobotMap robot;
  RobotGeometry g;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error)) << error;
  ASSERT_TRUE(GeometryFromModel(m, robot, &g, &error)) << error;
  mj_deleteModel(m);
  ASSERT_EQ(g.links[0].shapes.size(), 1u);
  EXPECT_EQ(g.links[0].shapes[0].type, ShapeType::kEllipsoid);
  EXPECT_EQ(g.links[0].shapes[0].size, Eigen::Vector3d(0.15, 0.12, 0.13));
  // the sphere on the ellipsoid's y axis 0.3 from its centre, semi-axis 0.12: gap 0.3 - 0.12 - 0.05
  auto c = SelfCollision::Create(g, &error);
  ASSERT_TRUE(c) << error;
  EXPECT_NEAR(c->Distance(0, 1, 1.0), 0.13, kTol);
  // the file keeps the type and the semi-axes
  SelfCollisionFile f, back;
  f.robot = g;
  f.online = NonAdjacentPairs(g);
  const std::string path = ohrp::testing::ScratchPath("egg", ".yaml");
  ASSERT_TRUE(WriteSelfCollisionFile(path, f, &error)) << error;
  ASSERT_TRUE(ReadSelfCollisionFile(path, &back, &error)) << error;
  EXPECT_EQ(back.robot.links[0].shapes[0].type, ShapeType::kEllipsoid);
  EXPECT_EQ(back.robot.links[0].shapes[0].size, Eigen::Vector3d(0.15, 0.12, 0.13));
  // a flat one is refused by Validate, naming the shape
  back.robot.links[0].shapes[0].size.z() = 0;
  EXPECT_FALSE(SelfCollision::Create(back.robot, &error));
  EXPECT_NE(error.find("ellipsoid"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::collision
