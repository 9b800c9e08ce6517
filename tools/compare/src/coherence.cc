// Whether two logs hold the same experiment (see coherence.h).
#include "compare/coherence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "compare/signal.h"

namespace ohrp::compare {

void Slice(const std::vector<double>& t, const std::vector<double>& x, double lo, double hi,
           std::vector<double>* ts, std::vector<double>* xs) {
  ts->clear();
  xs->clear();
  const size_t b = static_cast<size_t>(std::lower_bound(t.begin(), t.end(), lo) - t.begin());
  const size_t e = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), hi) - t.begin());
  if (e <= b) return;
  ts->assign(t.begin() + static_cast<long>(b), t.begin() + static_cast<long>(e));
  xs->assign(x.begin() + static_cast<long>(b), x.begin() + static_cast<long>(e));
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size());
  if (n < 3) return NAN;
  double ma = 0, mb = 0;
  for (size_t i = 0; i < n; ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= static_cast<double>(n);
  mb /= static_cast<double>(n);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (!(saa > 0) || !(sbb > 0)) return NAN;
  return sab / std::sqrt(saa * sbb);
}

bool Moves(const std::vector<double>& x) {
  if (x.size() < 3) return false;
  double mean = 0, magnitude = 0;
  for (double v : x) {
    mean += v;
    magnitude = std::max(magnitude, std::fabs(v));
  }
  mean /= static_cast<double>(x.size());
  double s2 = 0;
  for (double v : x) s2 += (v - mean) * (v - mean);
  const double spread = std::sqrt(s2 / static_cast<double>(x.size()));
  return spread > 3 * NoiseSigma(x) && spread > 1e-6 * magnitude;
}

Coherence JudgeCoherence(const std::vector<std::string>& names, const std::vector<double>& correlation,
                         const std::vector<bool>& moving_both, double threshold) {
  Coherence c;
  std::vector<double> r;
  std::string worst;
  double worst_r = 2;
  for (size_t i = 0; i < names.size(); ++i) {
    if (!moving_both[i] || std::isnan(correlation[i])) continue;
    r.push_back(correlation[i]);
    if (correlation[i] < worst_r) {
      worst_r = correlation[i];
      worst = names[i];
    }
  }
  c.moving = static_cast<int>(r.size());
  char buf[300];
  if (r.empty()) {
    c.median = NAN;
    c.same = true;
    c.detail = "no compared channel moves above its noise in both logs: whether they hold the same "
               "experiment cannot be told from them";
    return c;
  }
  std::sort(r.begin(), r.end());
  c.median = r.size() % 2 ? r[r.size() / 2] : 0.5 * (r[r.size() / 2 - 1] + r[r.size() / 2]);
  c.same = c.median >= threshold;
  std::snprintf(buf, sizeof(buf),
                "median correlation of the %d channels that move in both logs %.3f (lowest %s %.3f; "
                "threshold %.2f)",
                c.moving, c.median, worst.c_str(), worst_r, threshold);
  c.detail = buf;
  return c;
}

}  // namespace ohrp::compare
