// The offline pre-processing: structural, never-colliding and safe-range pairs, and the online
// list (collision/prune.h says how). Sampling finds candidates (prune_search.h); a pair is pruned
// only on a proof over the box of postures it relies on (prune_bound.h).
#include "collision/prune.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <tuple>

#include "collision/prune_bound.h"
#include "collision/self_collision.h"
#include "prune_search.h"

namespace ohrp::collision {
namespace {

using prune_search::Descend;
using prune_search::Mm;
using prune_search::Sampler;

// what the stages share
struct Run {
  Run(const RobotGeometry& g, const PruneOptions& opt, SelfCollision& checker, PruneResult& result)
      : robot(g), o(opt), c(checker), prover(&checker), sampler(opt, g.q_min, g.q_max),
        keep(opt.margin + opt.clearance), r(result), relies(result.all), pruned(result.all, 0),
        closest(result.all, INFINITY), near(result.all), witnesses(result.all) {}

  const RobotGeometry& robot;
  const PruneOptions& o;
  SelfCollision& c;
  PairProver prover;
  Sampler sampler;        // its lo/hi are the joints' current safe ranges (else their limits)
  double keep;            // margin + clearance [m]
  PruneResult& r;
  std::vector<std::vector<int>> relies;  // per pair, the joints whose ranges it relies on
  std::vector<char> pruned;              // per pair: never or by ranges (proven)
  std::vector<double> closest;           // per pair, the closest sampled distance [m]
  std::vector<std::vector<std::pair<double, std::vector<double>>>> near;  // closest samples
  std::vector<std::vector<std::vector<double>>> witnesses;  // per pair, postures within keep

  void Say(const std::string& s) const { if (o.progress) o.progress(s); }
  std::string Name(size_t i) const {
    return robot.links[r.pairs[i].a].name + " / " + robot.links[r.pairs[i].b].name;
  }
};

std::string Proof(const ProofResult& p) {
  return "certified " + Mm(p.certified) + ", " + std::to_string(p.boxes) + " boxes";
}

// 2. structural pairs: touching at the zero posture (clamped into the limits), or within the
// margin at the reference posture; each keeps a floor: the smaller of its distances at the two
// postures, less the margin
void FindStructural(Run& run) {
  const RobotGeometry& g = run.robot;
  const size_t njoint = static_cast<size_t>(NumJoints(g));  // actuated and passive
  std::vector<double> q0(njoint);
  for (size_t j = 0; j < njoint; ++j) q0[j] = std::clamp(0.0, g.q_min[j], g.q_max[j]);
  const bool has_ref = run.o.reference.size() == njoint;
  for (size_t i = 0; i < run.r.all; ++i) {
    const LinkPair p = run.r.pairs[i];
    run.c.SetPose(q0);
    const double d0 = run.c.Distance(p.a, p.b, 1e-6);
    double dref = INFINITY;
    if (has_ref) {
      run.c.SetPose(run.o.reference);
      dref = run.c.Distance(p.a, p.b, run.o.margin);
    }
    if (d0 > 1e-6 && dref > run.o.margin) continue;
    // the floor needs both distances measured, not bounded by a cutoff
    run.c.SetPose(q0);
    const double e0 = run.c.Distance(p.a, p.b, INFINITY);
    double eref = INFINITY;
    if (has_ref) {
      run.c.SetPose(run.o.reference);
      eref = run.c.Distance(p.a, p.b, INFINITY);
    }
    const double floor = std::min(e0, eref) - run.o.margin;
    run.r.file.structural.push_back(p);
    run.r.file.structural_floor.push_back(floor);
    run.r.reasons[i] = (d0 <= 1e-6 ? "structural: touching at the zero posture (" + Mm(e0) + ")"
                                   : "structural: within the margin at the reference posture (" +
                                         Mm(eref) + ")") +
                       ", checked online against its floor " + Mm(floor);
  }
}

// 3. samples within the limits: each pair's closest distance and closest postures (candidates
// for the proofs, and starts for descents)
void SampleLimits(Run& run) {
  std::vector<double> q;
  const double band = run.keep + run.o.descent_band;
  for (int s = 0; s < run.o.samples; ++s) {
    if (s % 5000 == 0)
      run.Say("sampling the limits: " + std::to_string(s) + "/" + std::to_string(run.o.samples));
    run.sampler.Sample(&q);
    run.c.SetPose(q);
    for (size_t i = 0; i < run.r.all; ++i) {
      if (!run.r.reasons[i].empty()) continue;
      const double d = run.c.Distance(run.r.pairs[i].a, run.r.pairs[i].b, band);
      run.closest[i] = std::min(run.closest[i], d);
      if (d <= run.keep && run.witnesses[i].size() < 32) run.witnesses[i].push_back(q);
      if (d > band) continue;
      auto& n = run.near[i];
      if (n.size() < 4 || d < n.back().first) {
        if (n.size() == 4) n.pop_back();
        n.emplace_back(d, q);
        std::sort(n.begin(), n.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      }
    }
  }
  // descents from the closest samples of the pairs the samples left clear
  for (size_t i = 0; i < run.r.all; ++i) {
    if (!run.r.reasons[i].empty() || run.closest[i] <= run.keep) continue;
    const std::vector<int> joints = JointsBetween(run.robot, run.r.pairs[i].a, run.r.pairs[i].b);
    for (const auto& start : run.near[i])
      run.closest[i] = std::min(run.closest[i], Descend(run.c, run.r.pairs[i], joints, start.second,
                                                        run.robot.q_min, run.robot.q_max, run.keep));
  }
}

// 4. never: proven clear over the joint limits
void ProveNever(Run& run) {
  for (size_t i = 0; i < run.r.all; ++i) {
    if (!run.r.reasons[i].empty() || run.closest[i] <= run.keep) continue;
    run.Say("proving never: " + run.Name(i));
    const ProofResult p = run.prover.Prove(run.r.pairs[i], run.robot.q_min, run.robot.q_max,
                                           run.keep, run.o.proof_budget);
    if (!p.proven) continue;
    run.pruned[i] = 1;
    run.r.reasons[i] = "never: proven farther than " + Mm(run.keep) + " over the joint limits (" +
                       Proof(p) + ")";
  }
}

// the restricted joints between pair i's links: those it relies on
std::vector<int> Restricted(const Run& run, size_t i) {
  std::vector<int> out;
  for (int j : JointsBetween(run.robot, run.r.pairs[i].a, run.r.pairs[i].b))
    if (run.sampler.lo()[j] > run.robot.q_min[j] || run.sampler.hi()[j] < run.robot.q_max[j])
      out.push_back(j);
  std::sort(out.begin(), out.end());
  return out;
}

// pair i proven clear over the box of the current ranges (`how`): it relies on the restricted
// joints
void Accept(Run& run, size_t i, const std::string& how) {
  run.pruned[i] = 1;
  run.relies[i] = Restricted(run, i);
  std::string why = "safe ranges:";
  for (int j : run.relies[i]) why += " " + JointName(run.robot, j);
  run.r.reasons[i] = why + "; proven farther than " + Mm(run.keep) + " " + how;
}

// a posture known to bring pair i within keep (a sample or a proof's counterexample) with joint
// j in [x0, x1] and every other joint within its current range: that cell is not safe
bool KnownUnsafe(const Run& run, size_t i, int j, double x0, double x1) {
  for (const auto& w : run.witnesses[i]) {
    if (w[j] < x0 || w[j] > x1) continue;
    bool inside = true;
    for (size_t k = 0; k < w.size() && inside; ++k)
      inside = static_cast<int>(k) == j ||
               (w[k] >= run.sampler.lo()[k] && w[k] <= run.sampler.hi()[k]);
    if (inside) return true;
  }
  return false;
}

// pair i proven clear with joint j in [x0, x1] and the other joints in their current ranges:
// first the known counterexamples and a few cheap samples, then the proof (a tenth of the budget)
bool CellProven(Run& run, size_t i, int j, double x0, double x1, int* boxes) {
  if (KnownUnsafe(run, i, j, x0, x1)) return false;
  const LinkPair p = run.r.pairs[i];
  std::vector<double> lo = run.sampler.lo(), hi = run.sampler.hi(), q;
  lo[j] = x0;
  hi[j] = x1;
  for (int k = 0; k < run.o.cell_samples; ++k) {
    run.sampler.SampleIn(lo, hi, &q);
    run.c.SetPose(q);
    if (run.c.Distance(p.a, p.b, run.keep) <= run.keep) {
      run.witnesses[i].push_back(q);
      return false;
    }
  }
  const ProofResult r = run.prover.Prove(p, lo, hi, run.keep, std::max(1, run.o.proof_budget / 10));
  *boxes += r.boxes;
  if (r.counterexample) run.witnesses[i].push_back(r.witness);
  return r.proven;
}

// the widest range of joint j around the reference over which pair i is proven clear (the other
// joints in their current ranges): proven cells outwards from the reference's (coarse), then
// proven sub-cells of the first unproven ones (fine); the range is a union of proven boxes, so it
// is proven. False when the reference's cell is not.
bool ProvenRangeOf(Run& run, size_t i, int j, double* lo, double* hi, int* boxes) {
  const double a = run.sampler.lo()[j], b = run.sampler.hi()[j], w = (b - a) / run.o.coarse;
  if (!(w > 0)) return false;
  const double ref = std::clamp(
      static_cast<size_t>(j) < run.o.reference.size() ? run.o.reference[j] : 0.0, a, b);
  const int c0 = std::min(run.o.coarse - 1, static_cast<int>((ref - a) / w));
  auto cell = [&](double x0, double x1) { return CellProven(run, i, j, x0, x1, boxes); };
  if (!cell(a + c0 * w, a + (c0 + 1) * w)) return false;
  int first = c0, last = c0;
  while (first > 0 && cell(a + (first - 1) * w, a + first * w)) --first;
  while (last < run.o.coarse - 1 && cell(a + (last + 1) * w, a + (last + 2) * w)) ++last;
  *lo = first == 0 ? a : a + first * w;
  *hi = last == run.o.coarse - 1 ? b : a + (last + 1) * w;
  const double f = w / run.o.fine;
  if (first > 0)
    for (int k = 0; k < run.o.fine && cell(*lo - f, *lo); ++k) *lo -= f;
  if (last < run.o.coarse - 1)
    for (int k = 0; k < run.o.fine && cell(*hi, *hi + f); ++k) *hi += f;
  return true;
}

// pair i: proven over the box of the ranges found so far, or over a new range of one of its
// joints (the widest proven); true when pruned
bool TryRanges(Run& run, size_t i) {
  const RobotGeometry& g = run.robot;
  const LinkPair p = run.r.pairs[i];
  if (!Restricted(run, i).empty()) {
    const ProofResult pr = run.prover.Prove(p, run.sampler.lo(), run.sampler.hi(), run.keep,
                                            run.o.proof_budget);
    if (pr.counterexample) run.witnesses[i].push_back(pr.witness);
    if (pr.proven) {
      Accept(run, i, "over the box of the ranges (" + Proof(pr) + ")");
      return true;
    }
  }
  int best = -1, boxes = 0;
  double best_share = 0, best_lo = 0, best_hi = 0;
  for (int j : JointsBetween(g, p.a, p.b)) {
    const auto& allowed = run.o.range_joints;
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), j) == allowed.end()) continue;
    double lo, hi;
    if (!ProvenRangeOf(run, i, j, &lo, &hi, &boxes)) continue;
    const double share = (hi - lo) / (g.q_max[j] - g.q_min[j]);
    if (share > best_share) best = j, best_share = share, best_lo = lo, best_hi = hi;
  }
  if (best < 0 || best_share < run.o.min_range_share) return false;
  run.sampler.lo()[best] = best_lo;
  run.sampler.hi()[best] = best_hi;
  Accept(run, i, "cell by cell over the box of the ranges (" + std::to_string(boxes) + " boxes)");
  return true;
}

// 5. safe ranges, pair by pair, in passes; the joints' ranges only shrink, so every proof made
// stays valid. A pair is tried again on a later pass only when the range of one of its joints
// changed since its last attempt.
void FindRanges(Run& run) {
  const RobotGeometry& g = run.robot;
  std::vector<int> version(static_cast<size_t>(NumJoints(g)), 0), tried(run.r.all, -1);
  auto state = [&](LinkPair p) {
    int v = 0;
    for (int j : JointsBetween(g, p.a, p.b)) v += version[j];
    return v;
  };
  bool changed = true;
  for (int pass = 0; pass < 3 && changed; ++pass) {
    changed = false;
    for (size_t i = 0; i < run.r.all; ++i) {
      if (!run.r.reasons[i].empty() || tried[i] == state(run.r.pairs[i])) continue;
      run.Say("safe ranges, pass " + std::to_string(pass + 1) + ": " + run.Name(i));
      tried[i] = state(run.r.pairs[i]);
      const std::vector<double> lo = run.sampler.lo(), hi = run.sampler.hi();
      if (!TryRanges(run, i)) continue;
      changed = true;
      for (size_t j = 0; j < version.size(); ++j)
        if (run.sampler.lo()[j] != lo[j] || run.sampler.hi()[j] != hi[j]) ++version[j];
    }
  }
}

// 6. a range that covers its joint's whole range restricts nothing: its pairs do not rely on it,
// and a pair left relying on nothing is a never pair (its proof covered the whole limits)
void DropWholeRanges(Run& run) {
  const RobotGeometry& g = run.robot;
  for (size_t i = 0; i < run.r.all; ++i) {
    if (!run.pruned[i] || run.relies[i].empty()) continue;
    auto& rel = run.relies[i];
    rel.erase(std::remove_if(rel.begin(), rel.end(), [&](int j) {
                return run.sampler.lo()[j] <= g.q_min[j] && run.sampler.hi()[j] >= g.q_max[j];
              }), rel.end());
    if (rel.empty())
      run.r.reasons[i] = "never (its ranges cover their joints' whole ranges): " + run.r.reasons[i];
  }
}

// 7. an independent check of the proofs by samples within the final ranges; a pruned pair within
// keep in one would be a bug of the bound: it goes back online, said so in the report
void CheckProofs(Run& run) {
  std::vector<double> q;
  for (int s = 0; s < run.o.verify; ++s) {
    if (s % 5000 == 0)
      run.Say("checking the proofs: " + std::to_string(s) + "/" + std::to_string(run.o.verify));
    run.sampler.Sample(&q);
    run.c.SetPose(q);
    for (size_t i = 0; i < run.r.all; ++i) {
      if (!run.pruned[i]) continue;
      const double d = run.c.Distance(run.r.pairs[i].a, run.r.pairs[i].b, run.keep);
      if (d > run.keep) continue;
      run.pruned[i] = 0;
      run.relies[i].clear();
      run.r.reasons[i] = "online: a sample came within " + Mm(run.keep) + " (" + Mm(d) +
                         ") despite its proof (a bug of the bound: report it)";
    }
  }
}

// 8. the file: never pairs, ranges with their pairs, the online list
void WriteLists(Run& run) {
  const size_t njoint = static_cast<size_t>(NumJoints(run.robot));
  std::vector<std::vector<LinkPair>> by_joint(njoint);
  for (size_t i = 0; i < run.r.all; ++i) {
    if (!run.pruned[i]) continue;
    if (run.relies[i].empty()) run.r.file.never.push_back(run.r.pairs[i]);
    for (int j : run.relies[i]) by_joint[j].push_back(run.r.pairs[i]);
  }
  for (size_t j = 0; j < njoint; ++j)
    if (!by_joint[j].empty())
      run.r.file.ranges.push_back({static_cast<int>(j),
                                   std::max(run.sampler.lo()[j], run.robot.q_min[j]),
                                   std::min(run.sampler.hi()[j], run.robot.q_max[j]), by_joint[j]});
  for (size_t i = 0; i < run.r.all; ++i) {
    if (run.pruned[i] || run.r.reasons[i].rfind("structural", 0) == 0) continue;
    run.r.file.online.push_back(run.r.pairs[i]);
    if (run.r.reasons[i].empty())
      run.r.reasons[i] = run.closest[i] <= run.keep
                             ? "online: came within " + Mm(run.keep) + " in the samples (" +
                                   Mm(run.closest[i]) + "), no proven safe range"
                             : "online: closest " + Mm(run.closest[i]) +
                                   " in the samples, not proven clear within the budget";
  }
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
  // 1. every non-adjacent pair
  r.pairs = NonAdjacentPairs(robot);
  r.all = r.pairs.size();
  r.reasons.assign(r.all, "");
  Run run(robot, o, *checker, r);
  // the stages, each timed for the report
  const std::pair<const char*, void (*)(Run&)> stages[] = {
      {"structural", FindStructural},   {"samples of the limits", SampleLimits},
      {"never proofs", ProveNever},     {"safe ranges", FindRanges},
      {"whole ranges", DropWholeRanges}, {"check of the proofs", CheckProofs},
      {"lists", WriteLists}};
  for (const auto& [name, stage] : stages) {
    const auto t0 = std::chrono::steady_clock::now();
    stage(run);
    r.stage_seconds.emplace_back(
        name, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  run.Say("");
  return r;
}

}  // namespace ohrp::collision
