// Checks of convex hulls shared by the hull tests (mesh_hull_test.cc) and the MJCF geometry
// tests (self_collision_hinges_test.cc).
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace ohrp::collision {

inline Eigen::Vector3d RandomDirection(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  return Eigen::Vector3d(n(*rng), n(*rng), n(*rng)).normalized();
}

inline double MaxAlong(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& u) {
  double best = -INFINITY;
  for (const Eigen::Vector3d& p : points) best = std::max(best, u.dot(p));
  return best;
}

// every triangle ("3, i, j, k") counter-clockwise from outside: no vertex in front of its plane
inline void ExpectOutwardTriangles(const std::vector<Eigen::Vector3d>& v, const std::vector<int>& faces) {
  ASSERT_EQ(faces.size() % 4, 0u);
  for (size_t f = 0; f < faces.size(); f += 4) {
    ASSERT_EQ(faces[f], 3);
    const Eigen::Vector3d& a = v[faces[f + 1]];
    const Eigen::Vector3d n = (v[faces[f + 2]] - a).cross(v[faces[f + 3]] - a);
    ASSERT_GT(n.norm(), 0) << "triangle " << f / 4 << " is degenerate";
    for (const Eigen::Vector3d& p : v)
      EXPECT_LE(n.normalized().dot(p - a), 1e-9) << "triangle " << f / 4 << " faces inwards";
  }
}

}  // namespace ohrp::collision
