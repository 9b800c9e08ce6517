// The exact distance of two boxes that do not overlap, in closed form: the smallest of the
// corner-to-box and edge-to-edge distances (the closest points of two disjoint convex polytopes
// are a vertex and a face, or two edges). The checker's fallback when FCL's GJK cannot certify
// its answer for a pair of boxes. Internal to ohrp::collision.
#pragma once

#include <Eigen/Geometry>

namespace ohrp::collision {

// Boxes of half-sizes h_a, h_b at poses X_WA, X_WB that do not overlap: their distance [m] and
// closest points (base frame). Meaningless for overlapping boxes (check that first).
double BoxBoxDistance(const Eigen::Isometry3d& X_WA, const Eigen::Vector3d& h_a,
                      const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& h_b,
                      Eigen::Vector3d* p_a, Eigen::Vector3d* p_b);

}  // namespace ohrp::collision
