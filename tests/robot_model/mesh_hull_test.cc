// The convex hull by Qhull (robot_model/collision/src/mesh_hull.h), for the meshes MuJoCo 2.2
// compiled without one (it makes a hull only where a colliding geom uses the mesh): a point set's
// hull has the point set's corners only, outward triangles, and the point set's support in any
// direction; flat or too few points are refused with the reason. The meshes of an MJCF (a
// visual-only cube, menagerie's H1) are tested in self_collision_hinges_test.cc.
#include "mesh_hull.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>

#include "hull_checks.h"

namespace ohrp::collision {
namespace {

TEST(MeshHull, HullOfAPointSet) {
  // a cube's corners and 200 points inside it
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1 ? 0.1 : -0.1, i & 2 ? 0.2 : -0.2, i & 4 ? 0.05 : -0.05);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.99, 0.99);
  for (int i = 0; i < 200; ++i) points.emplace_back(0.1 * u(rng), 0.2 * u(rng), 0.05 * u(rng));
  std::vector<Eigen::Vector3d> vertices;
  std::vector<int> faces;
  std::string error;
  ASSERT_TRUE(ConvexHull(points, &vertices, &faces, &error)) << error;
  EXPECT_EQ(vertices.size(), 8u);
  EXPECT_EQ(faces.size(), 4u * 12);
  ExpectOutwardTriangles(vertices, faces);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d = RandomDirection(&rng);
    EXPECT_NEAR(MaxAlong(vertices, d), MaxAlong(points, d), 1e-12);
  }
}

TEST(MeshHull, FlatOrTooFewPointsAreRefused) {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<int> faces;
  std::string error;
  const std::vector<Eigen::Vector3d> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 0}};
  EXPECT_FALSE(ConvexHull(flat, &vertices, &faces, &error));
  EXPECT_NE(error.find("span no volume"), std::string::npos) << error;
  EXPECT_TRUE(vertices.empty() && faces.empty());
  EXPECT_FALSE(ConvexHull({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, &vertices, &faces, &error));
  EXPECT_NE(error.find("at least 4"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::collision
