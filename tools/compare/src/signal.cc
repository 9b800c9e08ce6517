// Signal helpers of the log comparison (see signal.h).
#include "compare/signal.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "cli/plausible.h"

namespace ohrp::compare {

double Interpolate(const std::vector<double>& t, const std::vector<double>& x, double at,
                   size_t* cursor) {
  const size_t n = t.size();
  if (n == 0) return NAN;
  if (at <= t.front()) return x.front();
  if (at >= t.back()) return x.back();
  size_t i = std::min(*cursor, n - 2);
  if (t[i] > at) i = 0;
  while (i + 1 < n - 1 && t[i + 1] <= at) ++i;
  *cursor = i;
  const double u = (at - t[i]) / (t[i + 1] - t[i]);
  return x[i] + u * (x[i + 1] - x[i]);
}

double MedianStep(const std::vector<double>& t) {
  if (t.size() < 2) return 0;
  std::vector<double> d(t.size() - 1);
  for (size_t i = 0; i + 1 < t.size(); ++i) d[i] = t[i + 1] - t[i];
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

namespace {

// the series on the grid T0 + n h for n in [n0, n0 + size), less its mean
struct Gridded {
  long n0 = 0;
  std::vector<double> v;
};

Gridded OnGrid(const std::vector<double>& t, const std::vector<double>& x, double t0, double h) {
  Gridded g;
  g.n0 = static_cast<long>(std::ceil((t.front() - t0) / h - 1e-9));
  const long n1 = static_cast<long>(std::floor((t.back() - t0) / h + 1e-9));
  size_t cursor = 0;
  double mean = 0;
  for (long n = g.n0; n <= n1; ++n) {
    g.v.push_back(Interpolate(t, x, t0 + static_cast<double>(n) * h, &cursor));
    mean += g.v.back();
  }
  if (!g.v.empty()) mean /= static_cast<double>(g.v.size());
  for (double& v : g.v) v -= mean;
  return g;
}

}  // namespace

bool CrossCorrelationLag(const std::vector<double>& ta, const std::vector<double>& xa,
                         const std::vector<double>& tb, const std::vector<double>& xb,
                         double around, double max_lag, double* lag, std::string* error) {
  if (ta.size() < 3 || tb.size() < 3) {
    *error = "too few samples to cross-correlate";
    return false;
  }
  const double h = std::max(MedianStep(ta), MedianStep(tb));
  if (!(h > 0)) {
    *error = "the times do not increase";
    return false;
  }
  const double t0 = std::min(ta.front(), tb.front());
  // the grids' sizes, plausible numbers of samples before any is made: a log whose median step
  // is tiny beside its span (times of a file) would otherwise fill the memory or never end
  for (const auto& [t, name] : {std::pair{&ta, "A"}, std::pair{&tb, "B"}}) {
    const double samples = std::floor((t->back() - t0) / h) + 1;
    *error = cli::CheckPlausible("samples", samples,
                                 std::string("log ") + name + "'s time grid (its span / the median time step)");
    if (!error->empty()) return false;
  }
  const Gridded a = OnGrid(ta, xa, t0, h);
  const Gridded b = OnGrid(tb, xb, t0, h);
  auto flat = [](const Gridded& g) {
    double s = 0;
    for (double v : g.v) s += v * v;
    return !(s > 0);
  };
  if (flat(a) || flat(b)) {
    *error = std::string("the channel is constant in log ") + (flat(a) ? "A" : "B") +
             ": nothing to cross-correlate";
    return false;
  }
  const long na = static_cast<long>(a.v.size()), nb = static_cast<long>(b.v.size());
  // the lags searched, in grid steps, plausible numbers before they are longs: beyond `reach`
  // of the centre no lag has an overlap, so no more are searched than that
  const double center_steps = std::round(around / h);
  const double reach = std::fabs(static_cast<double>(b.n0 - a.n0)) + static_cast<double>(na + nb);
  const double k_steps = std::max(2.0, std::min(std::round(max_lag / h), reach + std::fabs(center_steps)));
  *error = cli::CheckPlausible("samples", std::fabs(center_steps) + 2,
                               "the lag searched around, in time steps (|lag| / the median time step)");
  if (error->empty())
    *error = cli::CheckPlausible("samples", 2 * k_steps + 1,
                                 "the lags searched (2 --max-lag / the median time step)");
  if (!error->empty()) return false;
  const long center = static_cast<long>(center_steps);
  const long k_max = static_cast<long>(k_steps);
  const long min_overlap = std::max<long>(3, std::min(na, nb) / 4);
  std::vector<double> c(static_cast<size_t>(2 * k_max + 1), NAN);
  long best = -1;
  for (long j = 0; j <= 2 * k_max; ++j) {
    const long k = center - k_max + j;  // B's grid index n + k pairs with A's n
    // A's n in [a.n0, a.n0 + na), B's n + k in [b.n0, b.n0 + nb)
    const long lo = std::max(a.n0, b.n0 - k), hi = std::min(a.n0 + na, b.n0 + nb - k);
    if (hi - lo < min_overlap) continue;
    double s = 0;
    for (long n = lo; n < hi; ++n) s += a.v[n - a.n0] * b.v[n + k - b.n0];
    c[j] = s;
    if (best < 0 || s > c[best]) best = j;
  }
  if (best < 0) {
    *error = "the logs do not overlap in time around the lag searched (--max-lag)";
    return false;
  }
  if (best == 0 || best == 2 * k_max || std::isnan(c[best - 1]) || std::isnan(c[best + 1])) {
    *error = "the cross-correlation peaks at the edge of the lags searched (" +
             std::to_string(around - max_lag) + " .. " + std::to_string(around + max_lag) +
             " s): raise --max-lag, or align on an event";
    return false;
  }
  const double cm = c[best - 1], c0 = c[best], cp = c[best + 1];
  const double den = cm - 2 * c0 + cp;
  const double frac = den < 0 ? 0.5 * (cm - cp) / den : 0.0;
  *lag = (static_cast<double>(center - k_max + best) + frac) * h;
  return true;
}

double NoiseSigma(const std::vector<double>& x, size_t begin, size_t end) {
  end = std::min(end, x.size());
  if (end < begin + 3) return 0;
  std::vector<double> d;
  d.reserve(end - begin);
  for (size_t i = begin + 1; i + 1 < end; ++i) d.push_back(std::fabs(x[i + 1] - 2 * x[i] + x[i - 1]));
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2] / (0.6745 * std::sqrt(6.0));
}

}  // namespace ohrp::compare
