#include "contact/geometry.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace ohrp::contact {
namespace {

// World AABB of a box given as a local centre/half extents under a pose.
void WorldAabb(const Eigen::Isometry3d& pose, const Eigen::Vector3d& center,
               const Eigen::Vector3d& half, Eigen::Vector3d* lo, Eigen::Vector3d* hi) {
  const Eigen::Vector3d c = pose * center;
  const Eigen::Vector3d h = pose.linear().cwiseAbs() * half;
  *lo = c - h;
  *hi = c + h;
}

}  // namespace

EnvObject EnvObject::Plane(std::string name, const Eigen::Isometry3d& pose) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kPlane;
  o.pose = pose;
  return o;
}

EnvObject EnvObject::Box(std::string name, const Eigen::Isometry3d& pose,
                         const Eigen::Vector3d& half_size) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kBox;
  o.pose = pose;
  o.shape = std::make_shared<fcl::Boxd>(2 * half_size.x(), 2 * half_size.y(), 2 * half_size.z());
  o.local_half = half_size;
  o.size = half_size;
  return o;
}

EnvObject EnvObject::Sphere(std::string name, const Eigen::Isometry3d& pose, double radius) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kSphere;
  o.pose = pose;
  o.shape = std::make_shared<fcl::Sphered>(radius);
  o.local_half = Eigen::Vector3d::Constant(radius);
  o.size = Eigen::Vector3d(radius, 0, 0);
  return o;
}

EnvObject EnvObject::Capsule(std::string name, const Eigen::Isometry3d& pose, double radius,
                             double half_length) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kCapsule;
  o.pose = pose;
  o.shape = std::make_shared<fcl::Capsuled>(radius, 2 * half_length);
  o.local_half = Eigen::Vector3d(radius, radius, radius + half_length);
  o.size = Eigen::Vector3d(radius, half_length, 0);
  return o;
}

EnvObject EnvObject::Cylinder(std::string name, const Eigen::Isometry3d& pose, double radius,
                              double half_length) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kCylinder;
  o.pose = pose;
  o.shape = std::make_shared<fcl::Cylinderd>(radius, 2 * half_length);
  o.local_half = Eigen::Vector3d(radius, radius, half_length);
  o.size = Eigen::Vector3d(radius, half_length, 0);
  return o;
}

EnvObject EnvObject::Convex(std::string name, const Eigen::Isometry3d& pose,
                            std::vector<Eigen::Vector3d> vertices,
                            const std::vector<int>& triangles) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kConvexMesh;
  o.pose = pose;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  o.local_center = 0.5 * (lo + hi);
  o.local_half = 0.5 * (hi - lo);
  // fcl::Convex's face encoding: for each face, its vertex count then the indices.
  auto faces = std::make_shared<std::vector<int>>();
  const int nface = static_cast<int>(triangles.size() / 3);
  faces->reserve(4 * nface);
  for (int f = 0; f < nface; ++f) {
    faces->push_back(3);
    for (int k = 0; k < 3; ++k) faces->push_back(triangles[3 * f + k]);
  }
  // Outward face planes of the hull, for the closed-form point query.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& v : vertices) mean += v;
  mean /= std::max<size_t>(1, vertices.size());
  for (int f = 0; f < nface; ++f) {
    const Eigen::Vector3d& a = vertices[triangles[3 * f]];
    const Eigen::Vector3d& b = vertices[triangles[3 * f + 1]];
    const Eigen::Vector3d& c = vertices[triangles[3 * f + 2]];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;  // degenerate triangle
    n.normalize();
    if (n.dot(a - mean) < 0) n = -n;  // outward
    o.planes.emplace_back(n.x(), n.y(), n.z(), n.dot(a));
  }
  auto verts = std::make_shared<std::vector<Eigen::Vector3d>>(std::move(vertices));
  auto convex = std::make_shared<fcl::Convexd>(verts, nface, faces, false);
  convex->computeLocalAABB();
  o.shape = convex;
  return o;
}

EnvObject EnvObject::HeightField(std::string name, const Eigen::Isometry3d& pose, int nrow,
                                 int ncol, double half_x, double half_y, double base,
                                 std::vector<double> heights) {
  EnvObject o;
  o.name = std::move(name);
  o.kind = EnvKind::kHeightField;
  o.pose = pose;
  o.hf_nrow = nrow;
  o.hf_ncol = ncol;
  o.hf_sx = half_x;
  o.hf_sy = half_y;
  o.hf_base = base;
  double top = 0;
  for (double z : heights) top = std::max(top, z);
  o.hf_z = std::move(heights);
  o.local_center = Eigen::Vector3d(0, 0, 0.5 * (top - base));
  o.local_half = Eigen::Vector3d(half_x, half_y, 0.5 * (top + base));
  return o;
}

namespace {

// Signed distance to a heightfield, local coordinates (see geometry.h).
double HeightFieldDistance(const EnvObject& o, const Eigen::Vector3d& x, Eigen::Vector3d* n_out) {
  *n_out = Eigen::Vector3d::UnitZ();
  const double dx = 2 * o.hf_sx / (o.hf_ncol - 1), dy = 2 * o.hf_sy / (o.hf_nrow - 1);
  const double gx = (x.x() + o.hf_sx) / dx, gy = (x.y() + o.hf_sy) / dy;
  if (gx < 0 || gy < 0 || gx > o.hf_ncol - 1 || gy > o.hf_nrow - 1) return 1.0;  // off the field
  if (x.z() < -o.hf_base) return -o.hf_base - x.z();                            // under it
  const int c0 = std::min(static_cast<int>(gx), o.hf_ncol - 2);
  const int r0 = std::min(static_cast<int>(gy), o.hf_nrow - 2);
  auto vertex = [&](int c, int r) {
    return Eigen::Vector3d(-o.hf_sx + c * dx, -o.hf_sy + r * dy, o.hf_z[r * o.hf_ncol + c]);
  };
  // Triangle t of cell (c, r): 0 = (c,r) (c+1,r) (c+1,r+1); 1 = (c,r) (c+1,r+1) (c,r+1).
  auto triangle = [&](int c, int r, int t, Eigen::Vector3d* a, Eigen::Vector3d* b,
                      Eigen::Vector3d* cc) {
    *a = vertex(c, r);
    *b = t == 0 ? vertex(c + 1, r) : vertex(c + 1, r + 1);
    *cc = t == 0 ? vertex(c + 1, r + 1) : vertex(c, r + 1);
  };
  // xy point-in-triangle (with a small tolerance, the triangles share edges).
  auto inside_xy = [](const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                      const Eigen::Vector3d& c) {
    const double d = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    if (std::abs(d) < 1e-15) return false;
    const double l1 = ((p.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (p.y() - a.y())) / d;
    const double l2 = ((b.x() - a.x()) * (p.y() - a.y()) - (p.x() - a.x()) * (b.y() - a.y())) / d;
    const double eps = 1e-9;
    return l1 >= -eps && l2 >= -eps && l1 + l2 <= 1 + eps;
  };
  // The triangle under the point: above its surface means outside.
  const int t0 = (gx - c0) >= (gy - r0) ? 0 : 1;
  Eigen::Vector3d a, b, c;
  triangle(c0, r0, t0, &a, &b, &c);
  Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  if (n.z() < 0) n = -n;
  const double under = n.dot(a - x);  // > 0: below the plane of the triangle under the point
  if (under <= 0) return -under;
  double best = under;
  *n_out = n;
  for (int r = std::max(0, r0 - 1); r <= std::min(o.hf_nrow - 2, r0 + 1); ++r) {
    for (int cc = std::max(0, c0 - 1); cc <= std::min(o.hf_ncol - 2, c0 + 1); ++cc) {
      for (int t = 0; t < 2; ++t) {
        if (r == r0 && cc == c0 && t == t0) continue;
        triangle(cc, r, t, &a, &b, &c);
        Eigen::Vector3d m = (b - a).cross(c - a);
        if (m.norm() < 1e-15) continue;
        m.normalize();
        if (m.z() < 0) m = -m;
        const double depth = m.dot(a - x);
        if (depth <= 0 || depth >= best) continue;
        if (!inside_xy(x + depth * m, a, b, c)) continue;  // cannot leave through it
        best = depth;
        *n_out = m;
      }
    }
  }
  return -best;
}

}  // namespace

namespace {

// n points from -h to h, the first and last on the edges, with trapezoid-rule weights summing
// to 1 (a single point sits in the middle with all the weight)
void AxisNodes(double h, int n, std::vector<double>* at, std::vector<double>* weight) {
  at->assign(n, 0.0);
  weight->assign(n, 1.0);
  if (n < 2) return;
  for (int i = 0; i < n; ++i) {
    (*at)[i] = -h + i * 2 * h / (n - 1);
    (*weight)[i] = (i == 0 || i == n - 1 ? 0.5 : 1.0) / (n - 1);
  }
}

}  // namespace

std::vector<SamplePoint> MakeGrid(const Eigen::Vector3d& half, int nx, int ny) {
  std::vector<double> ux, wx, vy, wy;
  AxisNodes(half.x(), nx, &ux, &wx);
  AxisNodes(half.y(), ny, &vy, &wy);
  std::vector<SamplePoint> grid;
  grid.reserve(nx * ny);
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      SamplePoint s;
      s.u = ux[i];
      s.v = vy[j];
      s.weight = wx[i] * wy[j];
      grid.push_back(s);
    }
  }
  return grid;
}

ContactGeometry::ContactGeometry(std::vector<EnvObject> env, double margin)
    : env_(std::move(env)), margin_(margin) {}

bool ContactGeometry::CheapBoundSeparated(const SoleBox& sole, const EnvObject& o) const {
  if (o.kind == EnvKind::kPlane) {
    // Lowest point of the whole sole box along the plane's normal.
    const Eigen::Vector3d n = o.pose.linear().col(2);
    const Eigen::Vector3d nl = sole.pose.linear().transpose() * n;  // normal in the sole frame
    const double center = n.dot(sole.pose.translation() - o.pose.translation());
    const double lowest = center - nl.cwiseAbs().dot(sole.half);
    return lowest > margin_;
  }
  Eigen::Vector3d slo, shi, olo, ohi;
  WorldAabb(sole.pose, Eigen::Vector3d::Zero(), sole.half, &slo, &shi);
  WorldAabb(o.pose, o.local_center, o.local_half, &olo, &ohi);
  for (int k = 0; k < 3; ++k) {
    if (slo[k] > ohi[k] + margin_ || olo[k] > shi[k] + margin_) return true;
  }
  return false;
}

double ContactGeometry::SignedDistance(const EnvObject& o, const Eigen::Vector3d& p,
                                       Eigen::Vector3d* normal) {
  const Eigen::Matrix3d& R = o.pose.linear();
  const Eigen::Vector3d x = R.transpose() * (p - o.pose.translation());  // local point
  Eigen::Vector3d n_local = Eigen::Vector3d::UnitZ();
  double sd = 0;
  switch (o.kind) {
    case EnvKind::kPlane:
      sd = x.z();
      break;
    case EnvKind::kBox: {
      // Inside: the nearest face is the axis with the largest |x_k| - h_k.
      int best = 0;
      sd = -std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k) {
        const double e = std::abs(x[k]) - o.size[k];
        if (e > sd) {
          sd = e;
          best = k;
        }
      }
      n_local = Eigen::Vector3d::Zero();
      n_local[best] = x[best] >= 0 ? 1.0 : -1.0;
      break;
    }
    case EnvKind::kSphere: {
      const double r = x.norm();
      sd = r - o.size[0];
      if (r > 1e-12) n_local = x / r;
      break;
    }
    case EnvKind::kCapsule: {
      const double hz = std::clamp(x.z(), -o.size[1], o.size[1]);
      const Eigen::Vector3d rel = x - Eigen::Vector3d(0, 0, hz);
      const double r = rel.norm();
      sd = r - o.size[0];
      n_local = r > 1e-12 ? Eigen::Vector3d(rel / r) : Eigen::Vector3d::UnitX();
      break;
    }
    case EnvKind::kCylinder: {
      const double rho = std::hypot(x.x(), x.y());
      const double side = rho - o.size[0];
      const double cap = std::abs(x.z()) - o.size[1];
      if (side > cap) {
        sd = side;
        n_local = rho > 1e-12 ? Eigen::Vector3d(x.x() / rho, x.y() / rho, 0)
                              : Eigen::Vector3d::UnitX();
      } else {
        sd = cap;
        n_local = Eigen::Vector3d(0, 0, x.z() >= 0 ? 1.0 : -1.0);
      }
      break;
    }
    case EnvKind::kHeightField:
      sd = HeightFieldDistance(o, x, &n_local);
      break;
    case EnvKind::kConvexMesh: {
      sd = -std::numeric_limits<double>::infinity();
      for (const Eigen::Vector4d& pl : o.planes) {
        const double e = pl.head<3>().dot(x) - pl[3];
        if (e > sd) {
          sd = e;
          n_local = pl.head<3>();
        }
      }
      break;
    }
  }
  if (normal) *normal = R * n_local;
  return sd;
}

void ContactGeometry::Find(const SoleBox& sole, const std::vector<SamplePoint>& grid,
                           std::vector<PointContact>* out, double reach) {
  out->clear();
  reach = std::clamp(reach, 0.0, margin_);
  candidates_.clear();
  for (int i = 0; i < static_cast<int>(env_.size()); ++i) {
    const EnvObject& o = env_[i];
    ++stats_.pairs_considered;
    if (CheapBoundSeparated(sole, o)) {
      ++stats_.pairs_bound;
      continue;
    }
    if (o.kind != EnvKind::kPlane && o.kind != EnvKind::kHeightField) {
      // One FCL distance between the whole sole box and the object: a sole that does not
      // touch the object cannot have a bottom point inside it.
      fcl::Boxd box(2 * sole.half.x(), 2 * sole.half.y(), 2 * sole.half.z());
      fcl::DistanceRequestd req;
      fcl::DistanceResultd res;
      ++stats_.fcl_queries;
      const double dist = fcl::distance(&box, fcl::Transform3d(sole.pose.matrix()), o.shape.get(),
                                        fcl::Transform3d(o.pose.matrix()), req, res);
      if (dist > reach) {
        ++stats_.pairs_fcl_far;
        continue;
      }
    }
    ++stats_.pairs_sampled;
    candidates_.push_back(i);
  }
  if (candidates_.empty()) return;

  for (int k = 0; k < static_cast<int>(grid.size()); ++k) {
    const Eigen::Vector3d p = sole.pose * Eigen::Vector3d(grid[k].u, grid[k].v, -sole.half.z());
    PointContact best;
    best.depth = -reach;  // the deepest wins; outside ones only within reach
    for (int i : candidates_) {
      Eigen::Vector3d n;
      const double sd = SignedDistance(env_[i], p, &n);
      if (sd < reach && -sd > best.depth) {
        best.index = k;
        best.object = i;
        best.pos = p;
        best.normal = n;
        best.depth = -sd;
      }
    }
    if (best.index >= 0) out->push_back(best);
  }
}

}  // namespace ohrp::contact
