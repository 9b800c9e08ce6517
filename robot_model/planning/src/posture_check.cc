// The validity check: the guard's pairs that the group moves, and the scene's boxes as fixed
// links of the checker's geometry.
#include "planning/posture_check.h"

#include <cmath>
#include <cstdio>

namespace ohrp::planning {
namespace {

// per link: does a joint of the group move it (its joint, or its parent's being moved)
std::vector<char> MovedLinks(const collision::RobotGeometry& robot, const JointGroup& group) {
  std::vector<char> moved(robot.links.size(), 0);
  for (size_t l = 0; l < robot.links.size(); ++l) {
    const collision::Link& link = robot.links[l];
    bool m = link.parent >= 0 && moved[link.parent];
    for (int id : group.ids) m = m || link.joint == id;
    moved[l] = m;
  }
  return moved;
}

std::vector<collision::LinkPair> WithMovingLink(const std::vector<collision::LinkPair>& pairs,
                                                const std::vector<char>& moved) {
  std::vector<collision::LinkPair> out;
  for (const auto& p : pairs)
    if (moved[p.a] || moved[p.b]) out.push_back(p);
  return out;
}

}  // namespace

std::unique_ptr<PostureCheck> PostureCheck::Create(const collision::SelfCollisionFile& file,
                                                   const std::vector<SceneBox>& scene,
                                                   const JointGroup& group, double clearance,
                                                   std::string* error) {
  if (!(clearance >= 0) || !std::isfinite(clearance)) {
    *error = "the planner's clearance must be a finite distance >= 0 m";
    return nullptr;
  }
  // the scene's boxes become fixed links after the robot's (root links: their pose is in the
  // base frame)
  collision::RobotGeometry robot = file.robot;
  const int nrobot = static_cast<int>(robot.links.size());
  for (const SceneBox& box : scene) {
    collision::Link l;
    l.name = "scene:" + box.name;
    l.p_PL = box.X_BO.translation();
    l.q_PL = Eigen::Quaterniond(box.X_BO.linear()).normalized();
    collision::Shape s;
    s.type = collision::ShapeType::kBox;
    s.size = box.half_size;
    l.shapes.push_back(s);
    robot.links.push_back(l);
  }
  std::unique_ptr<PostureCheck> c(new PostureCheck());
  c->checker_ = collision::SelfCollision::Create(robot, error);
  if (!c->checker_) return nullptr;
  c->group_ = group;
  c->nq_ = collision::NumJoints(robot);
  c->nrobot_ = nrobot;
  c->margin_ = file.margin;
  c->required_ = file.margin + clearance;
  const std::vector<char> moved = MovedLinks(robot, group);
  c->always_ = WithMovingLink(file.online, moved);
  for (int o = nrobot; o < static_cast<int>(robot.links.size()); ++o)
    for (int l = 0; l < nrobot; ++l)
      if (moved[l] && !robot.links[l].shapes.empty()) c->always_.push_back({l, o});
  for (const auto& r : file.ranges) {
    Range range{r.joint, r.lo, r.hi, WithMovingLink(r.pairs, moved)};
    if (!range.pairs.empty()) c->ranges_.push_back(std::move(range));
  }
  size_t most = c->always_.size();
  for (const auto& r : c->ranges_) most += r.pairs.size();
  c->pairs_.reserve(most);
  return c;
}

void PostureCheck::ListPairs(std::span<const double> q) {
  pairs_.assign(always_.begin(), always_.end());
  for (const Range& r : ranges_) {
    const double v = q[r.joint];
    if (v >= r.lo && v <= r.hi) continue;
    pairs_.insert(pairs_.end(), r.pairs.begin(), r.pairs.end());
  }
}

const std::vector<collision::LinkPair>& PostureCheck::PairsAt(std::span<const double> q) {
  ListPairs(q);
  return pairs_;
}

Verdict PostureCheck::Evaluate(std::span<const double> q) {
  ++evaluations_;
  ListPairs(q);
  checker_->SetPose(q);
  // a cutoff above the requirement: the closest pair's distance is exact up to it
  const collision::CheckResult r = checker_->Check(pairs_, required_ + 0.05, {});
  Verdict v;
  v.distance = r.min_distance;
  v.valid = r.min_distance >= required_;
  if (r.closest >= 0) {
    v.a = checker_->robot().links[pairs_[r.closest].a].name;
    v.b = checker_->robot().links[pairs_[r.closest].b].name;
  }
  return v;
}

void PostureCheck::EvaluateByKind(std::span<const double> q, Verdict* self, Verdict* scene) {
  ++evaluations_;
  ListPairs(q);
  checker_->SetPose(q);
  const double cutoff = required_ + 0.05;
  *self = Verdict();
  *scene = Verdict();
  self->distance = scene->distance = cutoff;
  const auto& links = checker_->robot().links;
  for (const auto& p : pairs_) {
    const double x = checker_->Distance(p.a, p.b, cutoff);
    Verdict* v = p.a >= nrobot_ || p.b >= nrobot_ ? scene : self;
    if (x < v->distance) {
      v->distance = x;
      v->a = links[p.a].name;
      v->b = links[p.b].name;
    }
  }
  self->valid = self->distance >= required_;
  scene->valid = scene->distance >= required_;
}

bool PostureCheck::Valid(std::span<const double> q) {
  ++evaluations_;
  ListPairs(q);
  checker_->SetPose(q);
  for (const auto& p : pairs_)
    if (checker_->Distance(p.a, p.b, required_) < required_) return false;
  return true;
}

std::string PostureCheck::Describe(const Verdict& v) const {
  char text[320];
  std::snprintf(text, sizeof text,
                "%s / %s at %.1f mm (the planner keeps %.1f mm: margin %.1f + clearance %.1f)",
                v.a.c_str(), v.b.c_str(), 1e3 * v.distance, 1e3 * required_, 1e3 * margin_,
                1e3 * (required_ - margin_));
  return text;
}

}  // namespace ohrp::planning
