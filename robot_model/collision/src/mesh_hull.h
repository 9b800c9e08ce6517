// The convex hull of a point set by Qhull, for meshes MuJoCo compiled without one (MuJoCo 2.2
// computes a mesh's hull only where a colliding geom uses it: a visual-only mesh, as every mesh
// of menagerie's H1, has none).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ohrp::collision {

// The hull of `points`: its vertices (a subset of the points) and its triangles, each as
// "3, i, j, k" into `vertices`, counter-clockwise seen from outside (FCL's Convex polygon list).
// False with Qhull's reason in `error` when the points span no volume (fewer than 4, flat).
bool ConvexHull(const std::vector<Eigen::Vector3d>& points, std::vector<Eigen::Vector3d>* vertices,
                std::vector<int>* faces, std::string* error);

}  // namespace ohrp::collision
