// The planner's validity check of a posture: the shared self-collision checker
// (collision/self_collision.h) on the pairs the online guard checks (the self-collision file's
// `online` pairs, plus the pairs of each safe range whose joint is outside its range; structural
// and never pairs are not checked, as online), and the scene's static boxes against every link
// the joint group moves (FCL through the same checker: each box is a fixed link of the
// geometry). Only pairs with a link the group moves are checked: the others do not change
// along a plan.
//
// A posture is valid when every checked pair is at least `required()` apart: the file's margin
// (where the guard stops a motion) plus the planner's clearance, so that a planned motion keeps
// that much room beyond what the guard needs.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "planning/joint_group.h"

namespace ohrp::planning {

// a static box of the scene, in the robot's base frame (the frame of the checker's postures)
struct SceneBox {
  std::string name;
  Eigen::Vector3d half_size = Eigen::Vector3d::Constant(0.1);  // [m]
  Eigen::Isometry3d X_BO = Eigen::Isometry3d::Identity();     // its pose in the base frame
};

// what one posture's check found
struct Verdict {
  bool valid = false;
  double distance = 0;  // the smallest signed distance of the checked pairs [m] (inf: none)
  std::string a, b;     // that pair's links (a box: "scene:NAME")
};

class PostureCheck {
 public:
  // The check of `file`'s robot moving `group` among `scene`, keeping `clearance` [m, >= 0]
  // beyond the file's margin. Null with `*error` for a geometry the checker refuses or a
  // clearance that is negative or not finite.
  static std::unique_ptr<PostureCheck> Create(const collision::SelfCollisionFile& file,
                                              const std::vector<SceneBox>& scene,
                                              const JointGroup& group, double clearance,
                                              std::string* error);

  // the distance every checked pair keeps [m]: margin + clearance
  double required() const { return required_; }
  double margin() const { return margin_; }
  const JointGroup& group() const { return group_; }
  int posture_size() const { return nq_; }

  // The verdict on a whole posture (NumJoints values). Allocates nothing.
  Verdict Evaluate(std::span<const double> posture);
  // Evaluate's closest pair split by kind: among the robot's own pairs (`self`) and among the
  // pairs with a scene box (`scene`); a kind with no pair within required() + 50 mm has the
  // cutoff as its distance and no names (for reports after a run: it copies the names)
  void EvaluateByKind(std::span<const double> posture, Verdict* self, Verdict* scene);
  // Evaluate's valid, stopping at the first pair closer than required()
  bool Valid(std::span<const double> posture);
  // evaluations since Create
  long evaluations() const { return evaluations_; }
  // the pairs this posture checks (the safe ranges it leaves included), for tests and tools
  const std::vector<collision::LinkPair>& PairsAt(std::span<const double> posture);
  const collision::SelfCollision& checker() const { return *checker_; }

  // "LARM_WRIST_R / CHEST at 3.1 mm (the planner keeps 12.0 mm: margin 2.0 + clearance 10.0)"
  std::string Describe(const Verdict& v) const;

 private:
  PostureCheck() = default;
  void ListPairs(std::span<const double> posture);

  std::unique_ptr<collision::SelfCollision> checker_;
  JointGroup group_;
  int nq_ = 0;
  int nrobot_ = 0;  // the robot's links; the scene's boxes follow them
  double margin_ = 0, required_ = 0;
  std::vector<collision::LinkPair> always_;   // online pairs with a moving link, scene pairs
  struct Range {
    int joint;
    double lo, hi;
    std::vector<collision::LinkPair> pairs;  // those with a moving link
  };
  std::vector<Range> ranges_;
  std::vector<collision::LinkPair> pairs_;    // this posture's list
  long evaluations_ = 0;
};

}  // namespace ohrp::planning
