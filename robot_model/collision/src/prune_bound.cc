// Branch and bound over boxes of postures: a pair proven clear, or a posture found within keep
// (collision/prune_bound.h says how).
#include "collision/prune_bound.h"

#include <algorithm>
#include <cmath>

#include "collision/incremental_check.h"
#include "collision/prune.h"

namespace ohrp::collision {

PairProver::PairProver(SelfCollision* checker)
    : c_(checker), reach_(LinkReach(checker->robot())) {
  const RobotGeometry& g = checker->robot();
  link_of_joint_.assign(static_cast<size_t>(NumJoints(g)), -1);
  centre_L_.assign(g.links.size(), Eigen::Vector3d::Zero());
  radius_.assign(g.links.size(), 0.0);
  for (size_t l = 0; l < g.links.size(); ++l) {
    const Link& link = g.links[l];
    if (link.joint >= 0) link_of_joint_[link.joint] = static_cast<int>(l);
    if (link.shapes.empty()) continue;
    // the centroid of the shapes' centres: inside the ball LinkReach's own reach assumes
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const Shape& s : link.shapes) c += s.p_LS;
    c /= static_cast<double>(link.shapes.size());
    centre_L_[l] = c;
    for (const Shape& s : link.shapes)
      radius_[l] = std::max(radius_[l], (s.p_LS - c).norm() + ShapeRadius(s));
  }
}

// Per side of the pair (link a, link b), the joints from the link upwards: each one's rho (the
// largest distance of a point of the link from its axis over the box) is at most the distance of
// the link's bounding sphere from the axis at the centre, plus the sphere's radius, plus how far
// the joints below it can move the sphere's centre over the box (sum of their half-widths times
// their rho: the centre is a point within their rho too), and at most LinkReach's reach.
double PairProver::MotionBound(LinkPair p, const std::vector<int>& joints,
                               const std::vector<double>& half,
                               std::vector<double>* weight) const {
  const RobotGeometry& g = c_->robot();
  weight->assign(joints.size(), 0.0);
  double m = 0;
  for (const int link : {p.a, p.b}) {
    const Eigen::Vector3d centre = c_->LinkPose(link) * centre_L_[link];
    double drift = 0;  // how far the sphere's centre can move relative to the next axis up [m]
    for (const auto& [k, reach] : reach_[link]) {
      const auto at = std::find(joints.begin(), joints.end(), k);
      if (at == joints.end()) continue;  // above the pair's common ancestor: moves both alike
      const Link& jl = g.links[link_of_joint_[k]];
      double rho = 1.0;  // a slide moves every point as far as itself
      if (!jl.slide) {
        const Eigen::Isometry3d& X = c_->LinkPose(link_of_joint_[k]);
        const Eigen::Vector3d axis = X.linear() * jl.axis_L;
        const Eigen::Vector3d v = centre - X * jl.anchor_L;
        rho = std::min(reach, (v - axis * axis.dot(v)).norm() + radius_[link] + drift);
      }
      const double w = std::max(half[k], 0.0) * rho;
      (*weight)[at - joints.begin()] += w;
      m += w;
      drift += w;
    }
  }
  return m;
}

ProofResult PairProver::Prove(LinkPair p, const std::vector<double>& lo,
                              const std::vector<double>& hi, double keep, int budget) {
  ProofResult r;
  r.certified = INFINITY;
  const std::vector<int> joints = JointsBetween(c_->robot(), p.a, p.b);
  const size_t n = joints.size();
  std::vector<double> q(lo.size()), half(lo.size(), 0.0), weight;
  for (size_t j = 0; j < lo.size(); ++j) q[j] = 0.5 * (lo[j] + hi[j]);
  // boxes to prove, each the lows then the highs of `joints`
  std::vector<std::vector<double>> stack;
  std::vector<double> box(2 * n);
  for (size_t i = 0; i < n; ++i) box[i] = lo[joints[i]], box[n + i] = hi[joints[i]];
  stack.push_back(box);
  while (!stack.empty()) {
    if (r.boxes >= budget) {  // not proven within the budget: the safe side
      r.certified = -INFINITY;
      return r;
    }
    box = std::move(stack.back());
    stack.pop_back();
    ++r.boxes;
    for (size_t i = 0; i < n; ++i) {
      q[joints[i]] = 0.5 * (box[i] + box[n + i]);
      half[joints[i]] = 0.5 * (box[n + i] - box[i]);
    }
    c_->SetPose(q);
    const double m = MotionBound(p, joints, half, &weight);
    const double d = c_->Distance(p.a, p.b, keep + m);
    if (d <= keep) {
      r.counterexample = true;
      r.certified = -INFINITY;
      r.witness = q;
      return r;
    }
    if (d - m > keep) {
      r.certified = std::min(r.certified, d - m);
      continue;
    }
    // split the joint that contributes most to the motion bound
    const size_t k = static_cast<size_t>(std::max_element(weight.begin(), weight.end()) - weight.begin());
    const double mid = q[joints[k]];
    std::vector<double> upper = box;
    upper[k] = mid;
    box[n + k] = mid;
    stack.push_back(std::move(upper));
    stack.push_back(std::move(box));
  }
  r.proven = true;
  return r;
}

}  // namespace ohrp::collision
