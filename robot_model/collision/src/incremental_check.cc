// Self-collision checks that skip the pairs whose links cannot have come within the cutoff
// (see incremental_check.h).
#include "collision/incremental_check.h"

#include <algorithm>
#include <cmath>

namespace ohrp::collision {
namespace {

// the largest distance of a point of `s` from its link's origin [m]
double ShapeReach(const Shape& s) { return s.p_LS.norm() + ShapeRadius(s); }

constexpr double kTolerance = 1e-6;  // [m] GJK's certification tolerance

}  // namespace

double ShapeRadius(const Shape& s) {
  switch (s.type) {
    case ShapeType::kSphere: return s.size[0];
    case ShapeType::kCapsule: return s.size[0] + s.size[1];
    case ShapeType::kCylinder: return std::hypot(s.size[0], s.size[1]);
    case ShapeType::kBox: return s.size.norm();
    case ShapeType::kEllipsoid: return s.size.maxCoeff();
    case ShapeType::kConvex: {
      double r = 0;
      for (const auto& v : s.vertices) r = std::max(r, v.norm());
      return r;
    }
  }
  return 0;
}

// A hinge: from its anchor to its link's origin, then down the chain, then the link's own
// shapes. A slide moves every point below it by exactly its own travel: 1 m per metre. Down the
// chain, a child's origin lies within |p_PL| + 2 |anchor_L| of its parent's whatever a hinge's
// angle, within |p_PL| + max(|q_min|, |q_max|) whatever a slide's position within its limits.
std::vector<std::vector<std::pair<int, double>>> LinkReach(const RobotGeometry& g) {
  const size_t n = g.links.size();
  std::vector<double> own(n, 0.0);
  for (size_t l = 0; l < n; ++l)
    for (const auto& s : g.links[l].shapes) own[l] = std::max(own[l], ShapeReach(s));
  std::vector<std::vector<std::pair<int, double>>> out(n);
  for (size_t l = 0; l < n; ++l) {
    double chain = 0;  // from the current link's origin down to link l's origin, bounded
    for (int k = static_cast<int>(l); k >= 0; k = g.links[k].parent) {
      const Link& link = g.links[k];
      if (link.joint >= 0 && link.slide) {
        out[l].emplace_back(link.joint, 1.0);
        chain += link.p_PL.norm() +
                 std::max(std::abs(g.q_min[link.joint]), std::abs(g.q_max[link.joint]));
      } else {
        if (link.joint >= 0)
          out[l].emplace_back(link.joint, link.anchor_L.norm() + chain + own[l]);
        chain += link.p_PL.norm() + 2 * link.anchor_L.norm();
      }
    }
  }
  return out;
}

IncrementalCheck::IncrementalCheck(SelfCollision* checker, std::vector<LinkPair> pairs)
    : checker_(checker), pairs_(std::move(pairs)), reach_(LinkReach(checker->robot())) {
  const size_t njoint = NumJoints(checker->robot());
  const size_t n = pairs_.size();
  q_.assign(njoint, 0.0);
  q_last_.assign(njoint, std::nan(""));
  travel_.assign(reach_.size(), 0.0);
  travel_a_.assign(n, 0.0);
  travel_b_.assign(n, 0.0);
  measured_d_.assign(n, -INFINITY);  // no measurement yet
  value_.assign(n, -INFINITY);
  measured_now_.assign(n, 0);
}

void IncrementalCheck::MoveTo(std::span<const double> q) {
  const size_t n = std::min(q.size(), q_.size());
  std::copy_n(q.begin(), n, q_.begin());
  bool unbounded = false;  // the first posture, or an angle that is not finite
  for (size_t l = 0; l < reach_.size(); ++l) {
    double m = 0;
    for (const auto& [joint, r] : reach_[l]) {
      const double dq = std::abs(q_[joint] - q_last_[joint]);
      if (std::isfinite(dq)) m += dq * r;
      else unbounded = true;
    }
    travel_[l] += m;
  }
  // no bound of the travel: every pair's last measurement is forgotten
  if (unbounded) std::fill(measured_d_.begin(), measured_d_.end(), -INFINITY);
  std::copy(q_.begin(), q_.end(), q_last_.begin());
}

double IncrementalCheck::Visit(int i, double cutoff, bool* posed) {
  const LinkPair& p = pairs_[i];
  const double travel = (travel_[p.a] - travel_a_[i]) + (travel_[p.b] - travel_b_[i]);
  const double bound = measured_d_[i] - travel;
  if (bound > cutoff + kTolerance) {
    ++skipped_;
    measured_now_[i] = 0;
    return value_[i] = bound;
  }
  if (!*posed) {
    checker_->SetPose(q_);
    *posed = true;
  }
  measured_d_[i] = checker_->Distance(p.a, p.b, cutoff);
  travel_a_[i] = travel_[p.a];
  travel_b_[i] = travel_[p.b];
  ++measured_;
  measured_now_[i] = 1;
  return value_[i] = measured_d_[i];
}

void IncrementalCheck::Record(int i, double d) {
  const LinkPair& p = pairs_[i];
  measured_d_[i] = value_[i] = d;
  travel_a_[i] = travel_[p.a];
  travel_b_[i] = travel_[p.b];
}

CheckResult IncrementalCheck::Check(std::span<const int> which, double cutoff) {
  CheckResult r;
  r.min_distance = INFINITY;
  bool posed = false;
  for (int i : which) {
    const double d = Visit(i, cutoff, &posed);
    if (d < r.min_distance) {
      r.min_distance = d;
      if (d <= cutoff) r.closest = i;
    }
  }
  return r;
}

CheckResult IncrementalCheck::CheckAll(double cutoff) {
  CheckResult r;
  r.min_distance = INFINITY;
  bool posed = false;
  for (int i = 0; i < static_cast<int>(pairs_.size()); ++i) {
    const double d = Visit(i, cutoff, &posed);
    if (d < r.min_distance) {
      r.min_distance = d;
      if (d <= cutoff) r.closest = i;
    }
  }
  return r;
}

}  // namespace ohrp::collision
