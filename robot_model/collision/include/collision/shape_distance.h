// The signed distance of two convex shapes placed in the world, for the tools that measure a
// robot against its surroundings after a run (the runner's obstacle_clearance check): the
// checker's own certified measurement (FCL's GJK, checked by the gap of the projections; boxes
// in closed form where GJK is off; overlapping shapes by their penetration depth), one shape at
// a time instead of a robot's links.
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "collision/geometry.h"

namespace ohrp::collision {

struct PreparedShape;

class ShapeDistance {
 public:
  // `shape` with its pose in its frame F (Shape::p_LS, q_LS: e.g. a geom in its body)
  explicit ShapeDistance(const Shape& shape);
  ~ShapeDistance();
  ShapeDistance(ShapeDistance&&) noexcept;
  ShapeDistance& operator=(ShapeDistance&&) noexcept;

  // the radius of a sphere about the shape's own origin that holds it [m], and that origin in F
  double radius() const;
  Eigen::Vector3d centre_F() const;

  // The signed distance [m] of this shape, its frame at X_WA, to `other`, its frame at X_WB:
  // > 0 the gap (certified: never more than the true gap), < 0 minus the penetration depth.
  double To(const Eigen::Isometry3d& X_WA, const ShapeDistance& other,
            const Eigen::Isometry3d& X_WB) const;

 private:
  Shape shape_;
  std::unique_ptr<PreparedShape> prepared_;
};

}  // namespace ohrp::collision
