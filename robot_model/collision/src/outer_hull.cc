// The outer polytope of a convex hull (outer_hull.h).
#include "outer_hull.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "mesh_hull.h"

namespace ohrp::collision {
namespace {

// the half-space n.x <= h (n unit)
struct Plane {
  Eigen::Vector3d n;
  double h;
};

// the point of triangle abc closest to p: p's projection on the triangle's plane when it falls
// inside, else the closest point of the edge or the corner whose region (of the plane's Voronoi
// partition by the triangle) holds it
Eigen::Vector3d ClosestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double s = 1 / (va + vb + vc);
  return a + ab * (vb * s) + ac * (vc * s);
}

// the plane moved out to the farthest vertex (a facet's plane holds them all but for rounding)
Plane PushedOut(Plane p, const std::vector<Eigen::Vector3d>& v) {
  for (const Eigen::Vector3d& q : v) p.h = std::max(p.h, p.n.dot(q));
  return p;
}

Eigen::Vector3d Mean(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : v) c += p;
  return c / static_cast<double>(std::max<size_t>(1, v.size()));
}

// the hull's facet planes, outwards (away from the vertices' mean, whichever way a triangle
// turns), each moved out to the farthest vertex: a sliver's rounded normal still bounds them all
std::vector<Plane> FacetPlanes(const std::vector<Eigen::Vector3d>& v, const std::vector<int>& faces) {
  const Eigen::Vector3d c = Mean(v);
  std::vector<Plane> planes;
  for (size_t f = 0; f + 3 < faces.size(); f += 4) {
    const Eigen::Vector3d& a = v[faces[f + 1]];
    Eigen::Vector3d n = (v[faces[f + 2]] - a).cross(v[faces[f + 3]] - a);
    if (n.norm() < 1e-15) continue;
    n.normalize();
    if (n.dot(a - c) < 0) n = -n;
    planes.push_back(PushedOut({n, n.dot(a)}, v));
  }
  return planes;
}

// the vertices of {x : n_i.x <= h_i}, bounded, with c strictly inside every half-space: with
// z = x - c the half-spaces are y_i.z <= 1, y_i = n_i / (h_i - n_i.c), and the polytope's
// vertices are the points a with a.y = 1 on a facet of the hull of the y_i (polar duality)
bool Corners(const std::vector<Plane>& planes, const Eigen::Vector3d& c,
             std::vector<Eigen::Vector3d>* out, std::string* error) {
  std::vector<Eigen::Vector3d> dual, dv;
  std::vector<int> df;
  for (const Plane& p : planes) dual.push_back(p.n / (p.h - p.n.dot(c)));
  if (!ConvexHull(dual, &dv, &df, error)) return false;
  out->clear();
  for (size_t f = 0; f + 3 < df.size(); f += 4) {
    Eigen::Matrix3d A;
    A << dv[df[f + 1]].transpose(), dv[df[f + 2]].transpose(), dv[df[f + 3]].transpose();
    const Eigen::Vector3d x = c + A.fullPivLu().solve(Eigen::Vector3d::Ones());
    // a corner where more than three planes meet comes from several triangles of one facet
    const bool known = std::any_of(out->begin(), out->end(), [&](const Eigen::Vector3d& y) {
      return (x - y).norm() < 1e-9;
    });
    if (!known) out->push_back(x);
  }
  return true;
}

// the facet plane p violates most (the largest n.p - h)
size_t MostViolated(const Eigen::Vector3d& p, const std::vector<Plane>& facets) {
  size_t best = 0;
  for (size_t f = 1; f < facets.size(); ++f)
    if (facets[f].n.dot(p) - facets[f].h > facets[best].n.dot(p) - facets[best].h) best = f;
  return best;
}

// p's distance from the hull of facets `facets` (triangles `faces` of `v`): 0 inside; outside,
// its boundary's, the closest of its triangles
double Distance(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& v,
                const std::vector<int>& faces, const std::vector<Plane>& facets) {
  if (std::all_of(facets.begin(), facets.end(), [&](const Plane& f) { return f.n.dot(p) <= f.h; }))
    return 0.0;
  double best = INFINITY;
  for (size_t f = 0; f + 3 < faces.size(); f += 4)
    best = std::min(best, (p - ClosestOnTriangle(p, v[faces[f + 1]], v[faces[f + 2]], v[faces[f + 3]])).norm());
  return best;
}

}  // namespace

double DistanceToHull(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& v,
                      const std::vector<int>& faces) {
  return Distance(p, v, faces, FacetPlanes(v, faces));
}

bool OuterPolytopeOf(const std::vector<Eigen::Vector3d>& vertices, const std::vector<int>& faces,
                     double tolerance, int max_planes, OuterPolytope* out, std::string* error) {
  const std::vector<Plane> facets = FacetPlanes(vertices, faces);
  const Eigen::Vector3d c = Mean(vertices);  // a point strictly inside
  double inner = INFINITY;
  for (const Plane& p : facets) inner = std::min(inner, p.h - p.n.dot(c));
  if (facets.size() < 4 || !(inner > 1e-9)) {
    *error = "the hull spans no volume";
    return false;
  }
  // 1. the supporting planes along the axes and the cube's diagonals: a bounded start
  std::vector<Plane> planes;
  for (int i = 0; i < 3; ++i)
    for (const double s : {-1.0, 1.0}) planes.push_back({s * Eigen::Vector3d::Unit(i), 0});
  for (int k = 0; k < 8; ++k)
    planes.push_back({Eigen::Vector3d(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1).normalized(), 0});
  for (Plane& p : planes) p = PushedOut({p.n, -INFINITY}, vertices);
  // 2. cut off the corner farthest from the hull, with the facet plane it violates most, until
  // every corner is within the tolerance (the Hausdorff distance of two convex polytopes, one
  // inside the other, is the largest distance of the outer one's corners)
  std::map<std::array<double, 3>, double> distance;  // of each corner met, measured once
  std::vector<Eigen::Vector3d> corners;
  for (;;) {
    if (!Corners(planes, c, &corners, error)) return false;
    double worst = 0;
    const Eigen::Vector3d* far = nullptr;
    for (const Eigen::Vector3d& x : corners) {
      const std::array<double, 3> key{x.x(), x.y(), x.z()};
      auto it = distance.find(key);
      if (it == distance.end()) it = distance.emplace(key, Distance(x, vertices, faces, facets)).first;
      if (it->second > worst) worst = it->second, far = &x;
    }
    out->excess = worst;
    if (!far || worst <= tolerance || static_cast<int>(planes.size()) >= max_planes) break;
    planes.push_back(facets[MostViolated(*far, facets)]);
  }
  out->planes = static_cast<int>(planes.size());
  return ConvexHull(corners, &out->vertices, &out->faces, error);
}

}  // namespace ohrp::collision
