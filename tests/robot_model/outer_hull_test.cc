// The outer polytope of a large convex hull (robot_model/collision/src/outer_hull.h): it contains
// the hull, stays within the tolerance of it and has fewer vertices. Closed forms: a point's
// distance from a cube; points on a sphere of radius R, whose hull lies inside the sphere, so a
// corner x of the polytope is at least |x| - R from it; a box is its own outer polytope. On
// menagerie's G1 (../shared/external): every mesh of the geometry holds all of MuJoCo's vertices
// of that mesh, within the tolerance, and each body keeps one of its visual and collision geom
// pair.
#include "outer_hull.h"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <random>

#include "collision/from_mjcf.h"
#include "hull_checks.h"
#include "mesh_hull.h"

namespace ohrp::collision {
namespace {

// the hull of `points` (Qhull)
void Hull(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>* v, std::vector<int>* f) {
  std::string error;
  ASSERT_TRUE(ConvexHull(points, v, f, &error)) << error;
}

TEST(OuterHull, DistanceToACube) {
  std::vector<Eigen::Vector3d> corners, v;
  std::vector<int> f;
  for (int i = 0; i < 8; ++i) corners.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  Hull(corners, &v, &f);
  EXPECT_NEAR(DistanceToHull({2, 0.5, 0.5}, v, f), 1.0, 1e-12);            // off a face
  EXPECT_NEAR(DistanceToHull({2, 2, 0.5}, v, f), std::sqrt(2.0), 1e-12);   // off an edge
  EXPECT_NEAR(DistanceToHull({2, 2, 2}, v, f), std::sqrt(3.0), 1e-12);     // off a corner
  EXPECT_NEAR(DistanceToHull({0.5, 0.5, -0.25}, v, f), 0.25, 1e-12);
  EXPECT_EQ(DistanceToHull({0.5, 0.2, 0.9}, v, f), 0.0);                  // inside
}

TEST(OuterHull, ABoxIsItsOwnOuterPolytope) {
  std::vector<Eigen::Vector3d> points, v;
  std::vector<int> f;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1 ? 0.1 : -0.1, i & 2 ? 0.03 : -0.03, i & 4 ? 0.2 : -0.2);
  for (int i = 0; i < 300; ++i) points.emplace_back(0.1 * u(rng), 0.03 * u(rng), 0.2 * u(rng));
  Hull(points, &v, &f);
  OuterPolytope out;
  std::string error;
  ASSERT_TRUE(OuterPolytopeOf(v, f, 0.002, 256, &out, &error)) << error;
  EXPECT_EQ(out.vertices.size(), 8u);
  EXPECT_LT(out.excess, 1e-12);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d d = RandomDirection(&rng);
    EXPECT_NEAR(MaxAlong(out.vertices, d), MaxAlong(points, d), 1e-12);
  }
}

// points on a sphere of radius R: the polytope holds them all, its corners are at most R + tol
// from the centre, its support exceeds theirs by at most its excess, and it has fewer vertices
TEST(OuterHull, ASphereWithinTheTolerance) {
  const double R = 0.08;
  std::vector<Eigen::Vector3d> points, v;
  std::vector<int> f;
  std::mt19937 rng(7);
  for (int i = 0; i < 1000; ++i) points.push_back(R * RandomDirection(&rng));
  Hull(points, &v, &f);
  for (const double tol : {0.008, 0.004, 0.002}) {
    OuterPolytope out;
    std::string error;
    ASSERT_TRUE(OuterPolytopeOf(v, f, tol, 1000, &out, &error)) << error;
    EXPECT_LE(out.excess, tol);
    EXPECT_LT(out.vertices.size(), v.size()) << "tolerance " << tol;
    ExpectOutwardTriangles(out.vertices, out.faces);
    for (size_t i = 0; i < out.vertices.size(); ++i) {
      const Eigen::Vector3d& x = out.vertices[i];
      EXPECT_LE(x.norm() - R, tol + 1e-12);
      // the exact distance agrees with the closed form's lower bound (a few corners: each
      // call measures the hull's planes again)
      if (i % 16 == 0) {
        EXPECT_GE(DistanceToHull(x, v, f), x.norm() - R - 1e-12);
      }
    }
    // the polytope contains the hull: no hull vertex beyond any of its faces
    for (size_t k = 0; k < out.faces.size(); k += 4) {
      const Eigen::Vector3d& a = out.vertices[out.faces[k + 1]];
      const Eigen::Vector3d n =
          (out.vertices[out.faces[k + 2]] - a).cross(out.vertices[out.faces[k + 3]] - a).normalized();
      for (const Eigen::Vector3d& p : points) ASSERT_LE(n.dot(p - a), 1e-9);
    }
    for (int i = 0; i < 200; ++i) {
      const Eigen::Vector3d d = RandomDirection(&rng);
      const double more = MaxAlong(out.vertices, d) - MaxAlong(points, d);
      EXPECT_GE(more, -1e-12);
      EXPECT_LE(more, out.excess + 1e-12);
    }
  }
}

TEST(OuterHull, AFlatHullIsRefused) {
  const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<int> f = {3, 0, 1, 2, 3, 0, 2, 1};
  OuterPolytope out;
  std::string error;
  EXPECT_FALSE(OuterPolytopeOf(v, f, 0.002, 256, &out, &error));
  EXPECT_NE(error.find("no volume"), std::string::npos) << error;
}

// menagerie's G1: meshes with up to 25,663 vertices (hulls of 224-3,567)
TEST(OuterHull, MenageriesG1MeshesAreHeldWithinTheTolerance) {
  const std::string path =
      std::string(OHRP_SOURCE_DIR) + "/../shared/external/menagerie/unitree_g1/g1.xml";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path << " is not there";
  char err[512] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, err, sizeof(err));
  ASSERT_TRUE(m) << err;
  model::RobotMap robot;
  RobotGeometry g;
  std::string error;
  ASSERT_TRUE(model::MapRobot(m, &robot, &error) && GeometryFromModel(m, robot, &g, &error)) << error;
  std::mt19937 rng(11);
  int meshes = 0;
  for (int b = 1; b < m->nbody; ++b) {
    const std::string body = mj_id2name(m, mjOBJ_BODY, b);
    const Link* link = nullptr;
    for (const Link& l : g.links) link = l.name == body ? &l : link;
    ASSERT_TRUE(link) << body;
    // each distinct mesh geom of the body once, in order
    size_t k = 0;
    std::vector<int> seen;
    for (int gid = m->body_geomadr[b]; gid < m->body_geomadr[b] + m->body_geomnum[b]; ++gid) {
      if (m->geom_type[gid] != mjGEOM_MESH) {
        ++k;
        continue;
      }
      const int mesh = m->geom_dataid[gid];
      if (std::find(seen.begin(), seen.end(), mesh) != seen.end()) continue;  // its twin
      seen.push_back(mesh);
      ASSERT_LT(k, link->shapes.size()) << body;
      const Shape& s = link->shapes[k++];
      ++meshes;
      const float* fv = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
      std::vector<Eigen::Vector3d> raw;
      for (int i = 0; i < m->mesh_vertnum[mesh]; ++i) raw.emplace_back(fv[3 * i], fv[3 * i + 1], fv[3 * i + 2]);
      EXPECT_LE(s.vertices.size(), 400u) << body;
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d d = RandomDirection(&rng);
        const double more = MaxAlong(s.vertices, d) - MaxAlong(raw, d);
        EXPECT_GE(more, -1e-6) << body;  // the mesh's floats, as doubles
        EXPECT_LE(more, kMeshHullTolerance + 1e-6) << body;
      }
    }
    EXPECT_EQ(k, link->shapes.size()) << body << ": a visual and a collision geom of one mesh, once";
  }
  EXPECT_GT(meshes, 25);
  mj_deleteModel(m);
}

}  // namespace
}  // namespace ohrp::collision
