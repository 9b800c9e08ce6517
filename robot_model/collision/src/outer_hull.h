// A convex hull with many vertices replaced by an outer polytope with few: an intersection of
// half-spaces bounded by the hull's own supporting planes, so it contains the hull (every
// distance the checker measures on it is a lower bound of the hull's: the safe side) and stays
// within a stated distance of it. The checker's cost (GJK's support function, the certificate)
// grows with the vertices; a scanned mesh's hull has hundreds to thousands (menagerie's G1:
// 224-3567 per mesh), its outer polytope at 2 mm a few dozen.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace ohrp::collision {

struct OuterPolytope {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<int> faces;  // triangles "3, i, j, k", counter-clockwise from outside (FCL's)
  double excess = 0;       // [m] its largest distance from the hull (Hausdorff: exact)
  int planes = 0;          // half-spaces it was cut from
};

// The outer polytope of the convex hull (`vertices`, triangles `faces` as ConvexHull gives
// them) within `tolerance` [m] of it: starts from the hull's supporting planes along the 14
// directions of the axes and the cube's diagonals, then, while a vertex of the polytope is
// farther than `tolerance` from the hull (the exact point-to-triangle distance), cuts it off with
// the hull facet's plane it violates most. At most `max_planes` planes: the excess it reaches is
// then in `excess`, above the tolerance. False with a reason when the hull spans no volume.
bool OuterPolytopeOf(const std::vector<Eigen::Vector3d>& vertices, const std::vector<int>& faces,
                     double tolerance, int max_planes, OuterPolytope* out, std::string* error);

// The distance [m] from point p to the convex hull (outward triangles "3, i, j, k"): 0 inside.
double DistanceToHull(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& vertices,
                      const std::vector<int>& faces);

}  // namespace ohrp::collision
