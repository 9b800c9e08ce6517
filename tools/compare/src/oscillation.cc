// Frequency and decay of a damped oscillation (see oscillation.h).
#include "compare/oscillation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "compare/damped_fit.h"
#include "compare/signal.h"

namespace ohrp::compare {
namespace {

// least-squares line y = a + b x; returns b, its standard error in *se (0 with 2 points)
double FitSlope(const std::vector<double>& x, const std::vector<double>& y, double* se,
                const std::vector<double>* weights = nullptr) {
  const size_t n = x.size();
  auto w = [&](size_t i) { return weights ? (*weights)[i] : 1.0; };
  double sw = 0, mx = 0, my = 0;
  for (size_t i = 0; i < n; ++i) {
    sw += w(i);
    mx += w(i) * x[i];
    my += w(i) * y[i];
  }
  mx /= sw;
  my /= sw;
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxx += w(i) * (x[i] - mx) * (x[i] - mx);
    sxy += w(i) * (x[i] - mx) * (y[i] - my);
  }
  const double b = sxy / sxx;
  double rss = 0;
  for (size_t i = 0; i < n; ++i) {
    const double r = y[i] - (my + b * (x[i] - mx));
    rss += w(i) * r * r;
  }
  *se = n > 2 ? std::sqrt(rss / static_cast<double>(n - 2) / sxx) : 0.0;
  return b;
}

// the vertex of the least-squares parabola through samples [lo, hi] (time and value); false
// when the fit has no vertex inside the span
bool Vertex(const std::vector<double>& t, const std::vector<double>& x, size_t lo, size_t hi,
            double* tv, double* xv) {
  if (hi < lo + 2) return false;
  const double tc = t[(lo + hi) / 2];
  // normal equations of x = c0 + c1 u + c2 u^2, u = t - tc
  double s[5] = {}, r[3] = {};
  for (size_t i = lo; i <= hi; ++i) {
    const double u = t[i] - tc;
    double p = 1;
    for (int k = 0; k < 5; ++k) {
      s[k] += p;
      if (k < 3) r[k] += p * x[i];
      p *= u;
    }
  }
  // solve the 3x3 system [s0 s1 s2; s1 s2 s3; s2 s3 s4] c = r (Cramer)
  auto det3 = [](double a, double b, double c, double d, double e, double f, double g, double h,
                 double k) { return a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g); };
  const double D = det3(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
  if (!(std::fabs(D) > 0)) return false;
  const double c0 = det3(r[0], s[1], s[2], r[1], s[2], s[3], r[2], s[3], s[4]) / D;
  const double c1 = det3(s[0], r[0], s[2], s[1], r[1], s[3], s[2], r[2], s[4]) / D;
  const double c2 = det3(s[0], s[1], r[0], s[1], s[2], r[1], s[2], s[3], r[2]) / D;
  if (c2 == 0) return false;
  const double u = -c1 / (2 * c2);
  if (u < t[lo] - tc || u > t[hi] - tc) return false;
  *tv = tc + u;
  *xv = c0 + c1 * u + c2 * u * u;
  return true;
}

// the figures of a damped sine fitted to [b, e) (damped_fit.h, from GridStart), reported with the
// regular extrema `te`, `xe` (at least one); *o unchanged but its `why` when the fit fails
void FromFit(const std::vector<double>& t, const std::vector<double>& x, size_t b, size_t e,
             const std::vector<double>& te, const std::vector<double>& xe, Oscillation* o) {
  double sigma0 = 0, omega0 = 0;
  if (!GridStart(t, x, b, e, &sigma0, &omega0)) {
    o->why += "; no start for a damped sine in the window";
    return;
  }
  const DampedFit fit = FitDampedSine(t, x, b, e, sigma0, omega0);
  if (!fit.ok || fit.explained < 0.5) {
    o->why += "; a damped sine fitted to the window: " +
              (fit.ok ? std::string("it explains under half of the signal") : fit.why);
    return;
  }
  const double td = 2 * M_PI / fit.omega;
  o->found = true;
  o->method = "fit";
  o->why.clear();
  o->extrema = static_cast<int>(te.size());
  o->first = t[b];
  o->last = t[e - 1];
  o->frequency = fit.omega / (2 * M_PI);
  o->frequency_se = fit.omega_se / (2 * M_PI);
  o->sigma = fit.sigma;
  o->sigma_se = fit.sigma_se;
  o->log_decrement = fit.sigma * td;
  // delta = 2 pi sigma / omega: its variance through the fit's covariance of sigma and omega
  const double ds = 2 * M_PI / fit.omega, dw = -2 * M_PI * fit.sigma / (fit.omega * fit.omega);
  o->log_decrement_se = std::sqrt(std::max(0.0, ds * ds * fit.sigma_se * fit.sigma_se +
                                                    dw * dw * fit.omega_se * fit.omega_se +
                                                    2 * ds * dw * fit.cov_sigma_omega));
  o->decay_ratio = std::exp(-o->log_decrement);
  o->damping_ratio = o->log_decrement / std::sqrt(4 * M_PI * M_PI + o->log_decrement * o->log_decrement);
  o->natural_frequency = o->frequency / std::sqrt(1 - o->damping_ratio * o->damping_ratio);
  o->amplitude = std::hypot(fit.a, fit.b);
  o->extremum_times = te;
  o->extremum_values = xe;
}

}  // namespace

Oscillation AnalyseOscillation(const std::vector<double>& t, const std::vector<double>& x,
                               double from, double to) {
  Oscillation o;
  const size_t b = static_cast<size_t>(std::lower_bound(t.begin(), t.end(), from) - t.begin());
  const size_t e = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), to) - t.begin());
  if (e < b + 8) {
    o.why = "fewer than 8 samples in the window";
    return o;
  }
  double lo = x[b], hi = x[b];
  for (size_t i = b; i < e; ++i) {
    lo = std::min(lo, x[i]);
    hi = std::max(hi, x[i]);
  }
  o.noise = NoiseSigma(x, b, e);
  // a swing below a millionth of the channel's magnitude is numerical (the solver's, the log's
  // nine digits), not motion: a standing robot's torque flat to 1e-7 N m makes no oscillation
  const double magnitude = std::max(std::fabs(lo), std::fabs(hi));
  if (!(hi - lo > 1e-6 * magnitude)) {
    char buf[200];
    std::snprintf(buf, sizeof(buf), "the channel is flat in the window: its range %.3g is below a millionth of its magnitude %.3g",
                  hi - lo, magnitude);
    o.why = buf;
    return o;
  }
  const double thr = std::max(6 * o.noise, 0.02 * (hi - lo));
  if (!(hi - lo > 2 * thr)) {
    o.why = "no swing above the noise in the window";
    return o;
  }

  // extrema with hysteresis: the first "extremum" is the window's start (not one), dropped
  std::vector<size_t> idx;
  int dir = 0;  // +1 tracking a maximum, -1 a minimum, 0 not yet known
  size_t ext = b;
  for (size_t i = b + 1; i < e; ++i) {
    if (dir == 0) {
      if (x[i] > x[b] + thr) dir = 1;
      else if (x[i] < x[b] - thr) dir = -1;
      ext = i;
      continue;
    }
    if (dir > 0) {
      if (x[i] > x[ext]) ext = i;
      else if (x[i] < x[ext] - thr) {
        idx.push_back(ext);
        dir = -1;
        ext = i;
      }
    } else {
      if (x[i] < x[ext]) ext = i;
      else if (x[i] > x[ext] + thr) {
        idx.push_back(ext);
        dir = 1;
        ext = i;
      }
    }
  }
  if (!idx.empty() && idx.front() <= b + 1) idx.erase(idx.begin());  // the window's edge
  if (idx.size() < 4) {
    o.why = "found " + std::to_string(idx.size()) + " extrema above the noise (need 4)";
    if (!idx.empty()) {  // damped heavily: the fit (below)
      std::vector<double> te, xe;
      for (size_t i : idx) {
        te.push_back(t[i]);
        xe.push_back(x[i]);
      }
      FromFit(t, x, b, e, te, xe, &o);
    }
    return o;
  }

  // refine each extremum: a parabola over +-15 % of the typical spacing (at least 2 samples)
  std::vector<size_t> gaps;
  for (size_t k = 0; k + 1 < idx.size(); ++k) gaps.push_back(idx[k + 1] - idx[k]);
  std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
  const size_t w = std::max<size_t>(2, static_cast<size_t>(0.3 * static_cast<double>(gaps[gaps.size() / 2])));
  std::vector<double> te, xe;
  for (size_t i : idx) {
    const size_t l = i >= b + w ? i - w : b, h = std::min(e - 1, i + w);
    double tv = t[i], xv = x[i];
    if (!Vertex(t, x, l, h, &tv, &xv)) {
      tv = t[i];
      xv = x[i];
    }
    te.push_back(tv);
    xe.push_back(xv);
  }

  // keep the regular part: from the first extremum on, while each half period is within 25 %
  // of the median one and each swing is above 16 noise sigma (in the tail, where the swings
  // sink into the noise, an extremum's time is noise's and one spurious extremum would shift
  // every index after it)
  double g = 0;  // the median half period
  {
    std::vector<double> half_periods;
    for (size_t i = 0; i + 1 < te.size(); ++i) half_periods.push_back(te[i + 1] - te[i]);
    std::nth_element(half_periods.begin(), half_periods.begin() + half_periods.size() / 2,
                     half_periods.end());
    g = half_periods[half_periods.size() / 2];
    size_t keep = 1;
    while (keep < te.size() && std::fabs(te[keep] - te[keep - 1] - g) < 0.25 * g &&
           std::fabs(xe[keep] - xe[keep - 1]) > 16 * o.noise)
      ++keep;
    te.resize(keep);
    xe.resize(keep);
  }
  if (te.size() < 4) {
    // damped too heavily for the extrema (soles with a damping ratio of 0.2 and more): a damped
    // sine fitted to the window, started from what the extrema say
    o.why = "found " + std::to_string(te.size()) + " regular extrema above the noise (need 4)";
    if (!te.empty()) FromFit(t, x, b, e, te, xe, &o);
    return o;
  }

  // period: extremum times against their index; decay: ln of the swings against time
  std::vector<double> k(te.size());
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<double>(i);
  double half_se = 0;
  const double half = FitSlope(k, te, &half_se);
  // each ln h weighted by the inverse of its variance: a swing h read between two noisy
  // extrema is off by about sqrt(2) noise sigma, so ln h by sqrt(2) sigma / h, with a floor of
  // 1 % for what is not noise. Unweighted, the last swings (a few sigma above the noise, which
  // one draw of noise keeps and another drops) would move the decay by 15 %.
  std::vector<double> ts, ls, ws;
  for (size_t i = 0; i + 1 < te.size(); ++i) {
    const double swing = std::fabs(xe[i + 1] - xe[i]);
    if (!(swing > 0)) continue;
    ts.push_back(0.5 * (te[i] + te[i + 1]));
    ls.push_back(std::log(swing));
    const double rel = std::sqrt(2.0) * o.noise / swing;
    ws.push_back(1 / (rel * rel + 1e-4));
  }
  if (ts.size() < 3 || !(half > 0)) {
    o.why = "the extrema do not make a regular oscillation";
    return o;
  }
  double slope_se = 0;
  const double slope = FitSlope(ts, ls, &slope_se, &ws);
  const double td = 2 * half;
  o.found = true;
  o.extrema = static_cast<int>(te.size());
  o.first = te.front();
  o.last = te.back();
  o.frequency = 1 / td;
  o.frequency_se = 2 * half_se / (td * td);
  o.sigma = -slope;
  o.sigma_se = slope_se;
  o.log_decrement = o.sigma * td;
  o.log_decrement_se = std::hypot(slope_se * td, o.sigma * 2 * half_se);
  o.decay_ratio = std::exp(-o.log_decrement);
  o.damping_ratio = o.log_decrement / std::sqrt(4 * M_PI * M_PI + o.log_decrement * o.log_decrement);
  o.natural_frequency = o.frequency / std::sqrt(std::max(1e-12, 1 - o.damping_ratio * o.damping_ratio));
  o.amplitude = 0.5 * std::exp(ls.front());
  o.extremum_times = te;
  o.extremum_values = xe;
  return o;
}

}  // namespace ohrp::compare
