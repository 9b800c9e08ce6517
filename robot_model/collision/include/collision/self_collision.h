// The self-collision checker (the paper's section 4.1): forward kinematics of the links from
// joint angles, a broad phase on bounding spheres, and per pair of links the signed distance of
// their closest shapes: the gap when apart (FCL's GJK on the convex shapes, each answer checked:
// the gap of the shapes' projections on the line of its closest points must equal it, else a
// pair of boxes is measured in closed form and other pairs get that gap, a lower bound; FCL 0.7's
// GJK overestimates some box pairs by up to 12 mm), minus the penetration depth when they overlap (a separating-axis search on the shapes' support
// functions: exact for boxes, an upper bound of the depth otherwise; a link inside another is
// a collision with the depth to push it out).
//
// SetPose and the Distance/Check calls allocate nothing, throw nothing and log nothing: a
// controller calls them every cycle. The checker is not thread-safe (SetPose writes its state).
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "collision/geometry.h"

namespace ohrp::collision {

class ShapeSet;  // the FCL shapes (src/shapes.h)

// what Check found
struct CheckResult {
  double min_distance = 0;  // the smallest signed distance of the checked pairs [m] (<= cutoff)
  int closest = -1;         // index in the pair list of that pair, -1 when none is within cutoff
  int narrow_queries = 0;   // shape pairs that reached GJK (the broad phase let them through)
  int uncertified = 0;      // of those, GJK answers the gap on their closest points' line did
                            // not confirm (then the exact box pair, or a lower bound, is used)
};

class SelfCollision {
 public:
  // Builds the checker of `robot` (Validate must pass). Returns null and sets `*error` on a
  // geometry Validate refuses.
  static std::unique_ptr<SelfCollision> Create(const RobotGeometry& robot, std::string* error);
  ~SelfCollision();
  SelfCollision(const SelfCollision&) = delete;
  SelfCollision& operator=(const SelfCollision&) = delete;

  const RobotGeometry& robot() const { return robot_; }

  // Places every link for the joint positions `q` (one per joint id: the actuated joints, then
  // the passive ones, NumJoints; [rad], [m] for slides). Non-finite angles are taken as zero.
  void SetPose(std::span<const double> q);
  // The same for links a and b only, and the links between them and the root (the same
  // arithmetic, so their poses equal SetPose's); the other links keep their last poses, so
  // only Distance(a, b, ...) is answered for q until the next SetPose. For the guard's
  // conservative advancement, which measures one pair at many postures.
  void SetPoseOf(std::span<const double> q, int a, int b);

  // The signed distance of links a and b at the pose of the last SetPose [m]: the gap between
  // their closest shapes, or minus the deepest penetration. When the pair is farther than
  // `cutoff` the broad phase may return any lower bound of the gap that exceeds `cutoff`.
  double Distance(int a, int b, double cutoff) const;

  // Distance of each pair of `pairs`, written to `distances` (same size, may be empty to skip
  // writing), and the closest of them.
  CheckResult Check(std::span<const LinkPair> pairs, double cutoff,
                    std::span<double> distances) const;

  // The signed distance of shape sa of link a and shape sb of link b [m] (as Distance, for one
  // pair of shapes; shapes are numbered in their link's order, as the MJCF's geoms).
  double ShapeDistance(int a, int sa, int b, int sb, double cutoff) const;

  // A second opinion on the same shape pair, independent of FCL: the largest gap of the
  // shapes' projections over unit axes found by a local search (the separating-axis search
  // that gives the penetration depth). A positive value proves the shapes apart and is a lower
  // bound of their distance; a negative one is minus an upper bound of the depth. For tests
  // and tools; it costs about a hundred support evaluations.
  double SupportDistance(int a, int sa, int b, int sb) const;

  // the pose of link i in the base frame after SetPose
  const Eigen::Isometry3d& LinkPose(int i) const { return X_WL_[i]; }

 private:
  explicit SelfCollision(const RobotGeometry& robot);
  // link i's pose from its parent's and q
  void PlaceLink(size_t i, std::span<const double> q);

  RobotGeometry robot_;
  std::unique_ptr<ShapeSet> shapes_;
  std::vector<Eigen::Isometry3d> X_WL_;   // link poses [m]
  std::vector<Eigen::Isometry3d> X_PL0_;  // each link in its parent at the joint's zero
  std::vector<char> on_path_;             // SetPoseOf's marks (all zero between calls)
  std::vector<Eigen::Vector3d> sphere_c_L_;  // each link's bounding sphere centre in the link
  std::vector<double> sphere_r_;             // and its radius [m]
  std::vector<Eigen::Vector3d> sphere_c_W_;  // the centres after SetPose [m]
  mutable int queries_ = 0, uncertified_ = 0;
};

}  // namespace ohrp::collision
