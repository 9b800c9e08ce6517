// The shapes of the checker: FCL's convex shapes for GJK, and the support functions that the
// penetration search uses. Internal to ohrp::collision.
#pragma once

#include <fcl/fcl.h>

#include <memory>
#include <vector>

#include "collision/geometry.h"

namespace ohrp::collision {

// one shape ready for queries
struct PreparedShape {
  const Shape* spec = nullptr;               // the description (owned by the checker's geometry)
  std::shared_ptr<fcl::CollisionGeometryd> fcl;  // the FCL shape, in the shape frame
  Eigen::Isometry3d X_LS = Eigen::Isometry3d::Identity();  // shape frame in the link frame
  double radius = 0;                         // bounding sphere about the shape frame's origin [m]
};

// one shape prepared for queries (`s` must outlive the result: it keeps a pointer)
PreparedShape Prepare(const Shape& s);

class ShapeSet {
 public:
  // the shapes of every link of `robot`, by link then shape (robot must outlive the set)
  explicit ShapeSet(const RobotGeometry& robot);
  const std::vector<PreparedShape>& of(int link) const { return links_[link]; }

 private:
  std::vector<std::vector<PreparedShape>> links_;
};

// The support function of a shape at pose X_WS: max over the shape of n . x, for a unit n.
double Support(const PreparedShape& s, const Eigen::Isometry3d& X_WS, const Eigen::Vector3d& n);

// The gap between two shapes by FCL's GJK (its own solver: no allocation) [m]; a value <= 0 when
// they touch or overlap.
double GjkDistance(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                   const Eigen::Isometry3d& X_WB);

// The penetration depth of two overlapping shapes [m] (>= 0): the smallest overlap of their
// projections over candidate axes (face normals, shape axes, their cross products, the line of
// centres) refined by a local search on the sphere of directions. Exact for two boxes; for
// curved shapes an upper bound within the search's resolution.
// The smallest overlap of the shapes' projections over unit axes, by the same search: > 0 is
// the penetration depth (as PenetrationDepth), < 0 is minus a lower bound of their distance,
// exact at the search's optimum (the distance of convex sets is the largest gap of their
// projections). Independent of FCL: the tests use it as a second opinion.
// `hint`, when not zero, is one more candidate axis (as the line between GJK's closest points,
// along which the gap is the distance).
double MinOverlap(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                  const Eigen::Isometry3d& X_WB, const Eigen::Vector3d& hint = Eigen::Vector3d::Zero());

// GjkDistance that also gives the closest points (in the base frame) [m]
double GjkDistance(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
                   const Eigen::Isometry3d& X_WB, Eigen::Vector3d* p_a, Eigen::Vector3d* p_b);

// The signed distance of two shapes [m] and, when apart, their closest points: FCL's GJK, its
// answer certified by the gap of the projections on the line of the closest points (a lower
// bound of the distance); when that gap differs by more than 1 um, two boxes are measured in
// closed form (BoxBoxDistance) and other pairs return the best lower bound found (safe side),
// and `*uncertified` counts it. Overlapping shapes: minus PenetrationDepth.
double Measure(const PreparedShape& a, const Eigen::Isometry3d& X_WA, const PreparedShape& b,
               const Eigen::Isometry3d& X_WB, Eigen::Vector3d* p_a, Eigen::Vector3d* p_b,
               int* uncertified);

double PenetrationDepth(const PreparedShape& a, const Eigen::Isometry3d& X_WA,
                        const PreparedShape& b, const Eigen::Isometry3d& X_WB);

}  // namespace ohrp::collision
