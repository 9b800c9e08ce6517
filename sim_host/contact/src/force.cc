#include "contact/force.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>

namespace ohrp::contact {
namespace {

// Fits depth = a + b u + c v (area-weighted) to the points of one object. A tiny ridge on the
// slopes keeps one point, or a single row of points, solvable (the slope along the missing
// direction is then 0, and the fitted depths at the points are the least-squares ones).
Eigen::Vector3d FitPlane(const std::vector<SamplePoint>& grid, const std::vector<PointContact>& pts,
                         const std::vector<int>& members, double scale2) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rhs = Eigen::Vector3d::Zero();
  for (int m : members) {
    const SamplePoint& s = grid[pts[m].index];
    const Eigen::Vector3d row(1.0, s.u, s.v);
    A += s.weight * row * row.transpose();
    rhs += s.weight * pts[m].depth * row;
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
  *out = SoleWrench{};
  proposed->assign(grid.size(), Anchor{});
  if (points.empty()) return;

  // 1. least-squares penetration per object.
  std::map<int, std::vector<int>> groups;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) groups[points[i].object].push_back(i);
  std::vector<double> fit(points.size());
  const double scale2 = sole.half.squaredNorm();
  size_t largest = 0;
  for (const auto& [object, members] : groups) {
    if (p.least_squares) {
      const Eigen::Vector3d abc = FitPlane(grid, points, members, scale2);
      for (int m : members) {
        const SamplePoint& s = grid[points[m].index];
        fit[m] = abc[0] + abc[1] * s.u + abc[2] * s.v;
      }
      if (members.size() > largest) {
        largest = members.size();
        out->depth = abc[0];
        out->tilt_u = abc[1];
        out->tilt_v = abc[2];
      }
    } else {
      for (int m : members) fit[m] = points[m].depth;
    }
  }

  Eigen::Vector3d cop_sum = Eigen::Vector3d::Zero();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  double vel_sum = 0;
  out->per_point.reserve(points.size());
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    const PointContact& c = points[i];
    const double w = grid[c.index].weight;
    PointForce f;
    f.index = c.index;
    f.object = c.object;
    f.pos = c.pos;
    f.normal = c.normal;
    f.depth = c.depth;
    f.depth_fit = std::max(fit[i], 0.0);
    const Eigen::Vector3d r = c.pos - sole.pose.translation();
    const Eigen::Vector3d v = twist.linear + twist.angular.cross(r);
    const double vn = v.dot(c.normal);
    f.pen_vel = -vn;
    // 2-4. spring and Hunt-Crossley damper, never pulling.
    const double spring = p.stiffness * w * std::pow(f.depth_fit, p.exponent);
    f.fn = std::max(0.0, spring * (1.0 + p.damping * f.pen_vel));
    // 5. friction: tangential spring-damper from the anchor, saturated by Coulomb.
    const Eigen::Vector3d vt = v - vn * c.normal;
    const Anchor& a = anchors.size() > static_cast<size_t>(c.index) ? anchors[c.index] : Anchor{};
    Eigen::Vector3d anchor = (a.active && a.object == c.object) ? a.pos : c.pos;
    Eigen::Vector3d s = c.pos - anchor;
    s -= s.dot(c.normal) * c.normal;
    const double kt = p.tangential_stiffness * w;
    Eigen::Vector3d ft = -kt * s - p.tangential_damping * w * vt;
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
    out->per_point.push_back(f);
  }
  out->in_contact = true;
  out->points = static_cast<int>(points.size());
  if (out->normal_force > 0) {
    out->point = cop_sum / out->normal_force;
    out->normal = normal_sum.normalized();
    out->penetration_velocity = vel_sum / out->normal_force;
  } else {
    out->point = centroid / static_cast<double>(points.size());
    out->normal = points.front().normal;
  }
  for (const PointForce& f : out->per_point) out->torque += (f.pos - out->point).cross(f.force);
}

}  // namespace ohrp::contact
