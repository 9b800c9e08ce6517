// Sampling that finds candidate safe ranges (prune_search.h).
#include "prune_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::collision::prune_search {
namespace {

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

}  // namespace

std::string Mm(double d) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.1f mm", 1e3 * d);
  return b;
}

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


}  // namespace ohrp::collision::prune_search
