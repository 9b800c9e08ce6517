// Sampling that finds candidate safe ranges (prune_search.h).
#include "prune_search.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::collision::prune_search {

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

}  // namespace ohrp::collision::prune_search
