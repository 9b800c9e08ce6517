// The offline pre-processing: structural, never-colliding and safe-range pairs, and the online
// list (collision/prune.h says how).
#include "collision/prune.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "collision/self_collision.h"

namespace ohrp::collision {
namespace {

std::string Mm(double d) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.1f mm", 1e3 * d);
  return b;
}

// postures within joint ranges: uniform, or at a limit with probability limit_share
class Sampler {
 public:
  Sampler(const PruneOptions& o, std::vector<double> lo, std::vector<double> hi)
      : o_(o), lo_(std::move(lo)), hi_(std::move(hi)), rng_(o.seed) {}
  std::vector<double>& lo() { return lo_; }
  std::vector<double>& hi() { return hi_; }

  void Sample(std::vector<double>* q) {
    q->resize(lo_.size());
    for (size_t j = 0; j < lo_.size(); ++j) {
      const double u = uniform_(rng_);
      if (u < o_.limit_share) (*q)[j] = u < 0.5 * o_.limit_share ? lo_[j] : hi_[j];
      else (*q)[j] = lo_[j] + uniform_(rng_) * (hi_[j] - lo_[j]);
    }
  }
  double Uniform(double a, double b) { return a + uniform_(rng_) * (b - a); }

 private:
  const PruneOptions& o_;
  std::vector<double> lo_, hi_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// a local descent of a pair's distance from posture q, over `joints` within [lo, hi]: the
// closest approach near a sampled posture, which random samples alone miss in many dimensions
double Descend(SelfCollision& c, LinkPair p, const std::vector<int>& joints, std::vector<double> q,
               const std::vector<double>& lo, const std::vector<double>& hi, double keep) {
  c.SetPose(q);
  double best = c.Distance(p.a, p.b, INFINITY);
  for (double step = 0.2; step >= 0.004 && best > keep; step *= 0.5) {
    for (bool improved = true; improved && best > keep;) {
      improved = false;
      for (int j : joints) {
        for (double sign : {1.0, -1.0}) {
          const double old = q[j];
          q[j] = std::clamp(old + sign * step, lo[j], hi[j]);
          if (q[j] == old) continue;
          c.SetPose(q);
          const double d = c.Distance(p.a, p.b, INFINITY);
          if (d < best) best = d, improved = true;
          else q[j] = old;
        }
      }
    }
  }
  return best;
}

// a pair stays beyond `keep` in cell_samples postures with joint j in [a, b] (the cell's ends
// first), the other joints sampled in their current ranges, and in descents from the closest
// two of them
bool CellSafe(SelfCollision& c, Sampler& s, const PruneOptions& o, LinkPair p,
              const std::vector<int>& joints, int j, double a, double b, double keep) {
  std::vector<double> q, lo = s.lo(), hi = s.hi();
  lo[j] = a;
  hi[j] = b;
  std::vector<std::pair<double, std::vector<double>>> closest;  // the closest two postures
  for (int k = 0; k < o.cell_samples; ++k) {
    s.Sample(&q);
    q[j] = k == 0 ? a : k == 1 ? b : s.Uniform(a, b);
    c.SetPose(q);
    const double d = c.Distance(p.a, p.b, keep + o.descent_band);
    if (d <= keep) return false;
    if (d > keep + o.descent_band) continue;
    closest.emplace_back(d, q);
    std::sort(closest.begin(), closest.end());
    if (closest.size() > 2) closest.pop_back();
  }
  for (const auto& [d, start] : closest)
    if (Descend(c, p, joints, start, lo, hi, keep) <= keep) return false;
  return true;
}

// the widest safe range of joint j around its zero posture for pair p, coarse then fine;
// false when the cell of the zero posture is not safe
bool SafeRangeOf(SelfCollision& c, Sampler& s, const PruneOptions& o, LinkPair p,
                 const std::vector<int>& joints, int j, double keep, double* lo, double* hi) {
  const double a = s.lo()[j], b = s.hi()[j], w = (b - a) / o.coarse;
  if (!(w > 0)) return false;
  const double ref = std::clamp(static_cast<size_t>(j) < o.reference.size() ? o.reference[j] : 0.0, a, b);
  const int c0 = std::min(o.coarse - 1, static_cast<int>((ref - a) / w));
  if (!CellSafe(c, s, o, p, joints, j, a + c0 * w, a + (c0 + 1) * w, keep)) return false;
  // coarse: whole cells outwards while safe
  int first = c0, last = c0;
  while (first > 0 && CellSafe(c, s, o, p, joints, j, a + (first - 1) * w, a + first * w, keep)) --first;
  while (last < o.coarse - 1 && CellSafe(c, s, o, p, joints, j, a + (last + 1) * w, a + (last + 2) * w, keep))
    ++last;
  *lo = a + first * w;
  *hi = a + (last + 1) * w;
  // fine: sub-cells of the unsafe neighbours, from the safe side outwards
  const double f = w / o.fine;
  if (first > 0)
    for (int k = 0; k < o.fine && CellSafe(c, s, o, p, joints, j, *lo - f, *lo, keep); ++k) *lo -= f;
  if (last < o.coarse - 1)
    for (int k = 0; k < o.fine && CellSafe(c, s, o, p, joints, j, *hi, *hi + f, keep); ++k) *hi += f;
  return true;
}

}  // namespace

std::vector<int> JointsBetween(const RobotGeometry& robot, int a, int b) {
  // the ancestors of a, then b's path up to the first of them
  std::vector<int> up_a;
  for (int l = a; l >= 0; l = robot.links[l].parent) up_a.push_back(l);
  std::vector<int> joints;
  int l = b;
  for (; l >= 0 && std::find(up_a.begin(), up_a.end(), l) == up_a.end(); l = robot.links[l].parent)
    if (robot.links[l].joint >= 0) joints.push_back(robot.links[l].joint);
  for (int k : up_a) {
    if (k == l) break;
    if (robot.links[k].joint >= 0) joints.push_back(robot.links[k].joint);
  }
  return joints;
}

PruneResult Prune(const RobotGeometry& robot, const PruneOptions& o) {
  PruneResult r;
  r.file.robot = robot;
  r.file.margin = o.margin;
  std::string error;
  auto checker = SelfCollision::Create(robot, &error);
  if (!checker) return r;
  SelfCollision& c = *checker;
  const double keep = o.margin + o.clearance;
  auto say = [&](const std::string& s) { if (o.progress) o.progress(s); };

  // 1. every non-adjacent pair
  r.pairs = NonAdjacentPairs(robot);
  r.all = r.pairs.size();
  r.reasons.assign(r.all, "");
  const size_t njoint = NumJoints(robot);  // actuated and passive

  // 2. structural: touching at the zero posture (clamped into the limits)
  std::vector<double> q0(njoint);
  for (size_t j = 0; j < njoint; ++j) q0[j] = std::clamp(0.0, robot.q_min[j], robot.q_max[j]);
  c.SetPose(q0);
  for (size_t i = 0; i < r.all; ++i) {
    const double d = c.Distance(r.pairs[i].a, r.pairs[i].b, 1e-6);
    if (d <= 1e-6) {
      r.file.structural.push_back(r.pairs[i]);
      r.reasons[i] = "structural: touching at the zero posture (" + Mm(d) + ")";
    }
  }
  // and within the margin at the reference posture (the online check would hold the robot
  // there: the thighs' tops enter the waist's box when the hips bend)
  if (o.reference.size() == njoint) {
    c.SetPose(o.reference);
    for (size_t i = 0; i < r.all; ++i) {
      if (!r.reasons[i].empty()) continue;
      const double d = c.Distance(r.pairs[i].a, r.pairs[i].b, o.margin);
      if (d > o.margin) continue;
      r.file.structural.push_back(r.pairs[i]);
      r.reasons[i] = "structural: within the margin at the reference posture (" + Mm(d) + ")";
    }
  }

  // 3. never: apart in every sample within the limits
  Sampler sampler(o, robot.q_min, robot.q_max);
  std::vector<double> closest(r.all, INFINITY), q;
  std::vector<std::vector<std::pair<double, std::vector<double>>>> near(r.all);
  for (int s = 0; s < o.samples; ++s) {
    if (s % 5000 == 0) say("sampling the limits: " + std::to_string(s) + "/" + std::to_string(o.samples));
    sampler.Sample(&q);
    c.SetPose(q);
    for (size_t i = 0; i < r.all; ++i) {
      if (!r.reasons[i].empty()) continue;
      const double d = c.Distance(r.pairs[i].a, r.pairs[i].b, keep + o.descent_band);
      closest[i] = std::min(closest[i], d);
      // the closest four postures of each pair, for the descents
      if (d > keep + o.descent_band) continue;
      auto& n = near[i];
      if (n.size() < 4 || d < n.back().first) {
        if (n.size() == 4) n.pop_back();
        n.emplace_back(d, q);
        std::sort(n.begin(), n.end());
      }
    }
  }
  for (size_t i = 0; i < r.all; ++i) {
    if (!r.reasons[i].empty() || closest[i] <= keep) continue;
    // near enough to doubt: descend from the closest samples
    if (closest[i] <= keep + o.descent_band) {
      const std::vector<int> joints = JointsBetween(robot, r.pairs[i].a, r.pairs[i].b);
      for (const auto& start : near[i])
        closest[i] = std::min(closest[i], Descend(c, r.pairs[i], joints, start.second,
                                                  robot.q_min, robot.q_max, keep));
      if (closest[i] <= keep) continue;
    }
    r.file.never.push_back(r.pairs[i]);
    r.reasons[i] = "never: farther than " + Mm(keep) + " in " + std::to_string(o.samples) +
                   " postures within the limits";
  }

  // 4. safe ranges, pair by pair; the joints' ranges only shrink
  std::vector<std::vector<LinkPair>> pruned_by(njoint);
  // passes: a range found for one pair narrows the samples of the next, so a pair left over may
  // be pruned on a later pass
  bool changed = true;
  for (int pass = 0; pass < 3 && changed; ++pass) {
  changed = false;
  for (size_t i = 0; i < r.all; ++i) {
    if (!r.reasons[i].empty()) continue;
    const LinkPair p = r.pairs[i];
    say("safe ranges: " + robot.links[p.a].name + " / " + robot.links[p.b].name);
    int best = -1;
    double best_share = 0, best_lo = 0, best_hi = 0;
    const std::vector<int> joints = JointsBetween(robot, p.a, p.b);
    for (int j : joints) {
      const auto& allowed = o.range_joints;
      if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), j) == allowed.end()) continue;
      double lo, hi;
      if (!SafeRangeOf(c, sampler, o, p, joints, j, keep, &lo, &hi)) continue;
      const double share = (hi - lo) / (robot.q_max[j] - robot.q_min[j]);
      if (share > best_share) best = j, best_share = share, best_lo = lo, best_hi = hi;
    }
    if (best < 0 || best_share < o.min_range_share) continue;
    changed = true;
    sampler.lo()[best] = best_lo;
    sampler.hi()[best] = best_hi;
    // the pair relies on every restricted joint between its links
    std::string why = "safe range: " + JointName(robot, best);
    for (int j : joints) {
      const bool restricted = sampler.lo()[j] > robot.q_min[j] || sampler.hi()[j] < robot.q_max[j];
      if (!restricted) continue;
      pruned_by[j].push_back(p);
      if (j != best) why += " + " + JointName(robot, j);
    }
    // safe in the whole of every range: it cannot collide while the others keep to theirs
    if (why.find(JointName(robot, best)) != std::string::npos &&
        sampler.lo()[best] == robot.q_min[best] && sampler.hi()[best] == robot.q_max[best] &&
        why.find(" + ") == std::string::npos) {
      r.file.never.push_back(p);
      why = "never: farther than " + Mm(keep) + " in every cell of the scans";
    }
    r.reasons[i] = why;
  }
  }
  // 5. verification: postures within the final ranges (each range kept or left at random); a
  // pruned pair that is uncovered (every range it relies on kept, or it is a never pair) and
  // comes within keep, in a sample or a descent from a near one, goes back online
  std::vector<std::vector<int>> relies(r.all);  // the joints each pruned pair relies on
  std::map<std::pair<int, int>, int> index;
  for (size_t i = 0; i < r.all; ++i) index[{r.pairs[i].a, r.pairs[i].b}] = static_cast<int>(i);
  for (size_t j = 0; j < njoint; ++j)
    for (const LinkPair& p : pruned_by[j]) relies[index[{p.a, p.b}]].push_back(static_cast<int>(j));
  std::vector<bool> pruned(r.all, false), back(r.all, false);
  std::vector<int> descents(r.all, 0);
  for (size_t i = 0; i < r.all; ++i)
    pruned[i] = !r.reasons[i].empty() && r.reasons[i].rfind("structural", 0) != 0;
  const std::vector<double> range_lo = sampler.lo(), range_hi = sampler.hi();
  std::mt19937_64 coin(o.seed + 1);
  for (int s = 0; s < o.verify; ++s) {
    if (s % 5000 == 0) say("verifying: " + std::to_string(s) + "/" + std::to_string(o.verify));
    // each restricted joint keeps its range with probability 1/2
    for (size_t j = 0; j < njoint; ++j) {
      const bool keep_range = coin() & 1;
      sampler.lo()[j] = keep_range ? range_lo[j] : robot.q_min[j];
      sampler.hi()[j] = keep_range ? range_hi[j] : robot.q_max[j];
    }
    sampler.Sample(&q);
    c.SetPose(q);
    for (size_t i = 0; i < r.all; ++i) {
      if (!pruned[i] || back[i]) continue;
      bool covered = false;  // a range it relies on is left: the online check takes it
      for (int j : relies[i]) covered = covered || q[j] < range_lo[j] || q[j] > range_hi[j];
      if (covered) continue;
      const double d = c.Distance(r.pairs[i].a, r.pairs[i].b, keep + o.descent_band);
      if (d > keep + o.descent_band) continue;
      // descend within the ranges it relies on (or the limits)
      std::vector<double> lo = robot.q_min, hi = robot.q_max;
      for (int j : relies[i]) lo[j] = range_lo[j], hi[j] = range_hi[j];
      const std::vector<int> joints = JointsBetween(robot, r.pairs[i].a, r.pairs[i].b);
      if (d <= keep) back[i] = true;
      else if (descents[i]++ < o.max_descents && Descend(c, r.pairs[i], joints, q, lo, hi, keep) <= keep)
        back[i] = true;
      c.SetPose(q);
    }
  }
  for (size_t i = 0; i < r.all; ++i) {
    if (!back[i]) continue;
    r.reasons[i] = "";  // online below
    auto drop = [&](std::vector<LinkPair>& v) {
      v.erase(std::remove(v.begin(), v.end(), r.pairs[i]), v.end());
    };
    drop(r.file.never);
    for (auto& list : pruned_by) drop(list);
  }
  for (size_t j = 0; j < njoint; ++j) {
    if (pruned_by[j].empty()) continue;
    r.file.ranges.push_back({static_cast<int>(j), sampler.lo()[j], sampler.hi()[j], pruned_by[j]});
  }
  // 6. the pairs left are checked online
  for (size_t i = 0; i < r.all; ++i) {
    if (!r.reasons[i].empty()) continue;
    r.file.online.push_back(r.pairs[i]);
    r.reasons[i] = back[i] ? "online: came within " + Mm(keep) + " in the verification"
                           : "online: closest " + Mm(closest[i]) + " in the samples, no safe range";
  }
  say("");
  return r;
}

}  // namespace ohrp::collision
