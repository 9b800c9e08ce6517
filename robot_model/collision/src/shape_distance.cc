// One shape against another in the world (collision/shape_distance.h).
#include "collision/shape_distance.h"

#include "shapes.h"

namespace ohrp::collision {

ShapeDistance::ShapeDistance(const Shape& shape)
    : shape_(shape), prepared_(std::make_unique<PreparedShape>(Prepare(shape_))) {}
ShapeDistance::~ShapeDistance() = default;
ShapeDistance::ShapeDistance(ShapeDistance&& o) noexcept
    : shape_(std::move(o.shape_)), prepared_(std::move(o.prepared_)) {
  if (prepared_) prepared_->spec = &shape_;  // the description moved with this object
}
ShapeDistance& ShapeDistance::operator=(ShapeDistance&& o) noexcept {
  shape_ = std::move(o.shape_);
  prepared_ = std::move(o.prepared_);
  if (prepared_) prepared_->spec = &shape_;
  return *this;
}

double ShapeDistance::radius() const { return prepared_->radius; }
Eigen::Vector3d ShapeDistance::centre_F() const { return prepared_->X_LS.translation(); }

double ShapeDistance::To(const Eigen::Isometry3d& X_WA, const ShapeDistance& other,
                         const Eigen::Isometry3d& X_WB) const {
  Eigen::Vector3d p_a, p_b;
  int uncertified = 0;  // an uncertain GJK answer falls back to a lower bound: the safe side
  return Measure(*prepared_, X_WA * prepared_->X_LS, *other.prepared_,
                 X_WB * other.prepared_->X_LS, &p_a, &p_b, &uncertified);
}

}  // namespace ohrp::collision
