#include "contact/force.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace ohrp::contact {
namespace {

// Fits depth = a + b u + c v (area-weighted) to the points touching `object`. A tiny ridge on
// the slopes keeps one point, or a single row of points, solvable (the slope along the missing
// direction is then 0, and the fitted depths at the points are the least-squares ones).
Eigen::Vector3d FitPlane(const std::vector<SamplePoint>& grid, const std::vector<PointContact>& pts,
                         int object, double scale2) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (const PointContact& c : pts) {
    if (c.object != object || c.depth <= 0) continue;
    const SamplePoint& s = grid[c.index];
    const Eigen::Vector3d row(1.0, s.u, s.v);
    A += s.weight * row * row.transpose();
    rhs += s.weight * c.depth * row;
  }
  const double ridge = 1e-9 * A(0, 0) * scale2;
  A(1, 1) += ridge;
  A(2, 2) += ridge;
  return A.ldlt().solve(rhs);
}

}  // namespace

void ComputeWrench(const SoftContactParams& p, const SoleBox& sole, const SoleTwist& twist,
                   const std::vector<SamplePoint>& grid, const std::vector<PointContact>& points,
                   const std::vector<Anchor>& anchors, std::vector<Anchor>* proposed,
                   SoleWrench* out) {
  // reset the result but keep the per-point storage: no allocation once it has grown
  std::vector<PointForce> per_point = std::move(out->per_point);
  *out = SoleWrench{};
  out->per_point = std::move(per_point);
  out->per_point.resize(points.size());
  proposed->assign(grid.size(), Anchor{});
  if (points.empty()) return;

  // 1. least-squares penetration per object (each object once, at its first point; the fitted
  // depths go straight into the per-point results).
  const double scale2 = sole.half.squaredNorm();
  int largest = 0;
  // (points outside within reach keep their own depth and take no part in the fit)
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].depth <= 0) {
      out->per_point[i].depth_fit = points[i].depth;
      continue;
    }
    const int object = points[i].object;
    bool seen = false;
    for (size_t j = 0; j < i && !seen; ++j) seen = points[j].object == object && points[j].depth > 0;
    if (seen) continue;
    if (!p.least_squares) {
      for (size_t k = i; k < points.size(); ++k)
        if (points[k].object == object && points[k].depth > 0)
          out->per_point[k].depth_fit = points[k].depth;
      continue;
    }
    const Eigen::Vector3d abc = FitPlane(grid, points, object, scale2);
    int members = 0;
    for (size_t k = i; k < points.size(); ++k) {
      if (points[k].object != object || points[k].depth <= 0) continue;
      const SamplePoint& s = grid[points[k].index];
      out->per_point[k].depth_fit = abc[0] + abc[1] * s.u + abc[2] * s.v;
      ++members;
    }
    if (members > largest) {
      largest = members;
      out->depth = abc[0];
      out->tilt_u = abc[1];
      out->tilt_v = abc[2];
    }
  }

  Eigen::Vector3d cop_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  double vel_sum = 0;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const PointContact& c = points[i];
    const double w = grid[c.index].weight;
    PointForce& f = out->per_point[i];
    const double fitted = f.depth_fit;
    f = PointForce{};
    f.index = c.index;
    f.object = c.object;
    f.pos = c.pos;
    f.normal = c.normal;
    f.depth = c.depth;
    f.depth_signed = fitted;
    f.depth_fit = std::max(fitted, 0.0);
    const Eigen::Vector3d r = c.pos - sole.pose.translation();
    const Eigen::Vector3d v = twist.linear + twist.angular.cross(r);
    const double vn = v.dot(c.normal);
    f.pen_vel = -vn;
    const Eigen::Vector3d vt = v - vn * c.normal;
    if (c.depth <= 0) {  // outside, within reach: no force, no anchor
      f.ft_trial = -p.tangential_damping * w * vt;
      continue;
    }
    // 2-4. spring and Hunt-Crossley damper, never pulling.
    const double spring =
        p.stiffness * w * (p.exponent == 1 ? f.depth_fit : std::pow(f.depth_fit, p.exponent));
    f.fn = std::max(0.0, spring * (1.0 + p.damping * f.pen_vel));
    // 5. friction: tangential spring-damper from the anchor, saturated by Coulomb.
    const Anchor& a = anchors.size() > static_cast<size_t>(c.index) ? anchors[c.index] : Anchor{};
    Eigen::Vector3d anchor = (a.active && a.object == c.object) ? a.pos : c.pos;
    Eigen::Vector3d s = c.pos - anchor;
    s -= s.dot(c.normal) * c.normal;
    const double kt = p.tangential_stiffness * w;
    Eigen::Vector3d ft = -kt * s - p.tangential_damping * w * vt;
    f.ft_trial = ft;
    const double limit = p.friction * f.fn;
    const double mag = ft.norm();
    if (mag > limit) {
      f.slipping = true;
      ft = mag > 0 ? Eigen::Vector3d(ft * (limit / mag)) : Eigen::Vector3d::Zero();
      // Drag the anchor so that the spring alone gives the saturated force.
      anchor = c.pos + ft / kt;
    } else {
      anchor = c.pos - s;  // unchanged, projected onto the current tangent plane
    }
    (*proposed)[c.index] = Anchor{true, c.object, anchor};
    f.force = f.fn * c.normal + ft;

    out->force += f.force;
    cop_sum += f.fn * c.pos;
    centroid += c.pos;
    normal_sum += f.fn * c.normal;
    vel_sum += f.fn * f.pen_vel;
    out->normal_force += f.fn;
    out->slipping += f.slipping ? 1 : 0;
  }
  int touching = 0;
  for (const PointContact& c : points) touching += c.depth > 0 ? 1 : 0;
  if (touching == 0) return;
  out->in_contact = true;
  out->points = touching;
  if (out->normal_force > 0) {
    out->point = cop_sum / out->normal_force;
    out->normal = normal_sum.normalized();
    out->penetration_velocity = vel_sum / out->normal_force;
  } else {
    out->point = centroid / static_cast<double>(touching);
    out->normal = points.front().normal;
  }
  for (const PointForce& f : out->per_point) out->torque += (f.pos - out->point).cross(f.force);
}

}  // namespace ohrp::contact
