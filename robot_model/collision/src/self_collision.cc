// The checker: link poses from joint angles, bounding spheres and the gap along the line of
// centres, then GJK or the penetration search per shape pair.
#include "collision/self_collision.h"

#include <algorithm>
#include <cmath>

#include "shapes.h"

namespace ohrp::collision {

std::unique_ptr<SelfCollision> SelfCollision::Create(const RobotGeometry& robot,
                                                     std::string* error) {
  const std::string problem = Validate(robot);
  if (!problem.empty()) {
    *error = "self-collision geometry: " + problem;
    return nullptr;
  }
  return std::unique_ptr<SelfCollision>(new SelfCollision(robot));
}

SelfCollision::SelfCollision(const RobotGeometry& robot) : robot_(robot) {
  shapes_ = std::make_unique<ShapeSet>(robot_);
  const size_t n = robot_.links.size();
  X_WL_.assign(n, Eigen::Isometry3d::Identity());
  sphere_c_L_.assign(n, Eigen::Vector3d::Zero());
  sphere_c_W_.assign(n, Eigen::Vector3d::Zero());
  sphere_r_.assign(n, 0.0);
  on_path_.assign(n, 0);
  // each link's fixed placement in its parent (the joint's motion comes after it)
  X_PL0_.assign(n, Eigen::Isometry3d::Identity());
  for (size_t l = 0; l < n; ++l) {
    X_PL0_[l].translate(robot_.links[l].p_PL);
    X_PL0_[l].rotate(robot_.links[l].q_PL.toRotationMatrix());
  }
  // each link's bounding sphere: centred on the box around its shapes' spheres
  for (size_t l = 0; l < n; ++l) {
    const auto& shapes = shapes_->of(static_cast<int>(l));
    if (shapes.empty()) continue;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (const auto& s : shapes) {
      lo = lo.cwiseMin(s.X_LS.translation() - Eigen::Vector3d::Constant(s.radius));
      hi = hi.cwiseMax(s.X_LS.translation() + Eigen::Vector3d::Constant(s.radius));
    }
    sphere_c_L_[l] = 0.5 * (lo + hi);
    for (const auto& s : shapes)
      sphere_r_[l] = std::max(sphere_r_[l], (s.X_LS.translation() - sphere_c_L_[l]).norm() + s.radius);
  }
  std::vector<double> zero(NumJoints(robot_), 0.0);
  SetPose(zero);
}

SelfCollision::~SelfCollision() = default;

void SelfCollision::PlaceLink(size_t i, std::span<const double> q) {
  const Link& l = robot_.links[i];
  Eigen::Isometry3d X_PL = X_PL0_[i];
  if (l.joint >= 0 && static_cast<size_t>(l.joint) < q.size()) {
    const double v = std::isfinite(q[l.joint]) ? q[l.joint] : 0.0;
    if (l.slide) {
      X_PL.translate(v * l.axis_L);
    } else {
      // a hinge through anchor_L: translate to it, turn, translate back
      X_PL.translate(l.anchor_L);
      X_PL.rotate(Eigen::AngleAxisd(v, l.axis_L));
      X_PL.translate(-l.anchor_L);
    }
  }
  X_WL_[i] = l.parent < 0 ? X_PL : X_WL_[l.parent] * X_PL;
  sphere_c_W_[i] = X_WL_[i] * sphere_c_L_[i];
}

void SelfCollision::SetPose(std::span<const double> q) {
  // forward kinematics down the tree (parents first); the base frame is the world
  for (size_t i = 0; i < robot_.links.size(); ++i) PlaceLink(i, q);
}

void SelfCollision::SetPoseOf(std::span<const double> q, int a, int b) {
  // the links from the root to a and to b (parents come before their children)
  int last = 0;
  for (int l : {a, b}) {
    last = std::max(last, l);
    for (int k = l; k >= 0 && !on_path_[k]; k = robot_.links[k].parent) on_path_[k] = 1;
  }
  for (int i = 0; i <= last; ++i)
    if (on_path_[i]) PlaceLink(static_cast<size_t>(i), q), on_path_[i] = 0;
}

double SelfCollision::ShapeDistance(int la, int sa, int lb, int sb, double cutoff) const {
  const PreparedShape& a = shapes_->of(la)[sa];
  const PreparedShape& b = shapes_->of(lb)[sb];
  const Eigen::Isometry3d X_WA = X_WL_[la] * a.X_LS, X_WB = X_WL_[lb] * b.X_LS;
  // broad phase: the shapes' bounding spheres
  const Eigen::Vector3d centres = X_WB.translation() - X_WA.translation();
  const double length = centres.norm();
  const double bound = length - a.radius - b.radius;
  if (bound > cutoff) return bound;
  // a tighter bound, nearly as cheap: the gap between the shapes' projections on the line of
  // their centres (the spheres of long shapes, limbs, are loose)
  if (length > 0) {
    const Eigen::Vector3d n = centres / length;
    const double gap = -(Support(a, X_WA, n) + Support(b, X_WB, -n));
    if (gap > cutoff) return gap;
  }
  ++queries_;
  Eigen::Vector3d p_a, p_b;
  return Measure(a, X_WA, b, X_WB, &p_a, &p_b, &uncertified_);
}

double SelfCollision::SupportDistance(int la, int sa, int lb, int sb) const {
  const PreparedShape& a = shapes_->of(la)[sa];
  const PreparedShape& b = shapes_->of(lb)[sb];
  const Eigen::Isometry3d X_WA = X_WL_[la] * a.X_LS, X_WB = X_WL_[lb] * b.X_LS;
  // the checker's closest points give one more axis; the gap along any axis bounds the
  // distance below
  Eigen::Vector3d p_a = Eigen::Vector3d::Zero(), p_b = Eigen::Vector3d::Zero();
  int ignored = 0;
  const double d = Measure(a, X_WA, b, X_WB, &p_a, &p_b, &ignored);
  const Eigen::Vector3d hint = d > 0 ? Eigen::Vector3d(p_b - p_a) : Eigen::Vector3d::Zero();
  return -MinOverlap(a, X_WA, b, X_WB, hint);
}

double SelfCollision::Distance(int a, int b, double cutoff) const {
  // broad phase: the links' bounding spheres
  const double reach = sphere_r_[a] + sphere_r_[b] + cutoff;
  const double d2 = (sphere_c_W_[a] - sphere_c_W_[b]).squaredNorm();
  if (d2 > reach * reach) return std::sqrt(d2) - sphere_r_[a] - sphere_r_[b];
  double d = INFINITY;
  const int na = static_cast<int>(shapes_->of(a).size()), nb = static_cast<int>(shapes_->of(b).size());
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) d = std::min(d, ShapeDistance(a, i, b, j, cutoff));
  return d;
}

CheckResult SelfCollision::Check(std::span<const LinkPair> pairs, double cutoff,
                                 std::span<double> distances) const {
  CheckResult r;
  r.min_distance = INFINITY;
  queries_ = uncertified_ = 0;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const double d = Distance(pairs[k].a, pairs[k].b, cutoff);
    if (k < distances.size()) distances[k] = d;
    if (d < r.min_distance) {
      r.min_distance = d;
      if (d <= cutoff) r.closest = static_cast<int>(k);
    }
  }
  r.narrow_queries = queries_;
  r.uncertified = uncertified_;
  return r;
}

}  // namespace ohrp::collision
