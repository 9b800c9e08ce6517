// The checker's shapes: FCL shapes from the geometry, support functions, GJK distance by type,
// and the penetration depth of overlapping shapes.
#include "shapes.h"

#include "box_distance.h"
#include "collision/incremental_check.h"

#include <algorithm>
#include <cmath>

namespace ohrp::collision {
namespace {

// the FCL shape of a description (sizes are FCL's full lengths)
std::shared_ptr<fcl::CollisionGeometryd> MakeFcl(const Shape& s) {
  switch (s.type) {
    case ShapeType::kSphere: return std::make_shared<fcl::Sphered>(s.size.x());
    case ShapeType::kCapsule: return std::make_shared<fcl::Capsuled>(s.size.x(), 2 * s.size.y());
    case ShapeType::kCylinder: return std::make_shared<fcl::Cylinderd>(s.size.x(), 2 * s.size.y());
    case ShapeType::kBox: return std::make_shared<fcl::Boxd>(2 * s.size);
    case ShapeType::kEllipsoid: return std::make_shared<fcl::Ellipsoidd>(s.size);
    case ShapeType::kConvex: {
      auto verts = std::make_shared<std::vector<Eigen::Vector3d>>(s.vertices);
      auto faces = std::make_shared<std::vector<int>>(s.faces);
      int nface = 0;
      for (size_t i = 0; i < s.faces.size(); i += s.faces[i] + 1) ++nface;
      return std::make_shared<fcl::Convexd>(verts, nface, faces, false);
    }
  }
  return nullptr;
}

// calls f with the concrete FCL type of a prepared shape
template <typename F>
auto Visit(const PreparedShape& s, F&& f) {
  const fcl::CollisionGeometryd* g = s.fcl.get();
  switch (s.spec->type) {
    case ShapeType::kSphere: return f(*static_cast<const fcl::Sphered*>(g));
    case ShapeType::kCapsule: return f(*static_cast<const fcl::Capsuled*>(g));
    case ShapeType::kCylinder: return f(*static_cast<const fcl::Cylinderd*>(g));
    case ShapeType::kBox: return f(*static_cast<const fcl::Boxd*>(g));
    case ShapeType::kEllipsoid: return f(*static_cast<const fcl::Ellipsoidd*>(g));
    case ShapeType::kConvex: break;
  }
  return f(*static_cast<const fcl::Convexd*>(g));
}

// FCL's own GJK (stack only, unlike its libccd solver, which allocates per query)
const fcl::detail::GJKSolver_indep<double>& Solver() {
  static const fcl::detail::GJKSolver_indep<double> solver;
  return solver;
}

// the overlap of the two shapes' projections on the unit axis n [m]
double Overlap(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
               const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& n) {
  return Support(a, X_WA, n) + Support(b, X_WB, -n);
}

}  // namespace

PreparedShape Prepare(const Shape& s) {
  PreparedShape p;
  p.spec = &s;
  p.fcl = MakeFcl(s);
  p.X_LS.setIdentity();
  p.X_LS.translate(s.p_LS);
  p.X_LS.rotate(s.q_LS.normalized().toRotationMatrix());
  p.radius = ShapeRadius(s);  // collision/incremental_check.h
  return p;
}

ShapeSet::ShapeSet(const RobotGeometry& robot) {
  links_.resize(robot.links.size());
  for (size_t l = 0; l < robot.links.size(); ++l)
    for (const Shape& s : robot.links[l].shapes) links_[l].push_back(Prepare(s));
}

double Support(const PreparedShape& s, const Eigen::Isometry3d& X_WS, const Eigen::Vector3d& n) {
  const Eigen::Matrix3d& R = X_WS.linear();
  const Eigen::Vector3d n_S = R.transpose() * n;  // the direction in the shape frame
  const double c = n.dot(X_WS.translation());
  const Eigen::Vector3d& h = s.spec->size;
  switch (s.spec->type) {
    case ShapeType::kSphere: return c + h.x();
    case ShapeType::kCapsule: return c + h.y() * std::abs(n_S.z()) + h.x();
    case ShapeType::kCylinder:
      return c + h.y() * std::abs(n_S.z()) + h.x() * std::hypot(n_S.x(), n_S.y());
    case ShapeType::kBox: return c + h.dot(n_S.cwiseAbs());
    // max of n.x over x^T diag(h)^-2 x <= 1: |diag(h) n| (exact)
    case ShapeType::kEllipsoid: return c + h.cwiseProduct(n_S).norm();
    case ShapeType::kConvex: {
      double m = -INFINITY;
      for (const auto& v : s.spec->vertices) m = std::max(m, n_S.dot(v));
      return c + m;
    }
  }
  return c;
}

double GjkDistance(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                   const Eigen::Isometry3d& X_WB) {
  Eigen::Vector3d p_a, p_b;  // FCL's capsule pair asserts that it gets the closest points
  return GjkDistance(a, X_WA, b, X_WB, &p_a, &p_b);
}

double GjkDistance(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                   const Eigen::Isometry3d& X_WB, Eigen::Vector3d* p_a, Eigen::Vector3d* p_b) {
  const fcl::Transform3d tf_a(X_WA.matrix()), tf_b(X_WB.matrix());
  double d = -1;
  const bool apart = Visit(a, [&](const auto& sa) {
    return Visit(b, [&](const auto& sb) {
      return Solver().shapeDistance(sa, tf_a, sb, tf_b, &d, p_a, p_b);
    });
  });
  return apart ? d : 0.0;
}

double PenetrationDepth(const PreparedShape& a, const Eigen::Isometry3d& X_WA,
                        const PreparedShape& b, const Eigen::Isometry3d& X_WB) {
  return std::max(MinOverlap(a, X_WA, b, X_WB), 0.0);
}

double MinOverlap(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                  const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& hint) {
  // candidate axes: each shape's frame axes, their cross products, the line of centres
  Eigen::Vector3d axes[17];
  int n = 0;
  for (int i = 0; i < 3; ++i) axes[n++] = X_WA.linear().col(i);
  for (int i = 0; i < 3; ++i) axes[n++] = X_WB.linear().col(i);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) axes[n++] = X_WA.linear().col(i).cross(X_WB.linear().col(j));
  axes[n++] = X_WB.translation() - X_WA.translation();
  axes[n++] = hint;
  double best = INFINITY;
  Eigen::Vector3d best_n = Eigen::Vector3d::UnitZ();
  for (int k = 0; k < n; ++k) {
    const double len = axes[k].norm();
    if (len < 1e-9) continue;
    const Eigen::Vector3d u = axes[k] / len;
    // both signs: the overlap along -u differs when the shapes are not centred
    for (const Eigen::Vector3d& v : {u, Eigen::Vector3d(-u)}) {
      const double o = Overlap(a, X_WA, b, X_WB, v);
      if (o < best) best = o, best_n = v;
    }
  }
  // refine on the sphere of directions: a pattern search with a shrinking step
  for (double step = 0.25; step > 1e-3; step *= 0.5) {
    for (bool improved = true; improved;) {
      improved = false;
      const Eigen::Vector3d t1 = best_n.unitOrthogonal(), t2 = best_n.cross(t1);
      for (const Eigen::Vector3d& d : {t1, Eigen::Vector3d(-t1), t2, Eigen::Vector3d(-t2)}) {
        const Eigen::Vector3d v = (best_n + step * d).normalized();
        const double o = Overlap(a, X_WA, b, X_WB, v);
        if (o < best - 1e-12) best = o, best_n = v, improved = true;
      }
    }
  }
  return best;
}

double Measure(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
               const Eigen::Isometry3d& X_WB, Eigen::Vector3d* p_a, Eigen::Vector3d* p_b,
               int* uncertified) {
  constexpr double kCertified = 1e-6;  // [m] GJK's answer against its lower bound
  const double gap = GjkDistance(a, X_WA, b, X_WB, p_a, p_b);
  if (gap > 0) {
    // the certificate: the gap of the projections on the line of the closest points
    const Eigen::Vector3d n = (*p_b - *p_a).normalized();
    const double lower = -Overlap(a, X_WA, b, X_WB, n);
    if (gap - lower <= kCertified) return gap;
    ++*uncertified;
  }
  // GJK uncertain, or overlapping: the separating-axis search (exact overlap test for boxes)
  const Eigen::Vector3d hint = gap > 0 ? Eigen::Vector3d(*p_b - *p_a) : Eigen::Vector3d::Zero();
  const double o = MinOverlap(a, X_WA, b, X_WB, hint);
  if (o >= 0) return -o;
  if (a.spec->type == ShapeType::kBox && b.spec->type == ShapeType::kBox)
    return BoxBoxDistance(X_WA, a.spec->size, X_WB, b.spec->size, p_a, p_b);
  return -o;  // apart by at least this much
}

}  // namespace ohrp::collision
