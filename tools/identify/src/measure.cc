// The oscillation of a log's channel, measured alike on the recording and the simulations
// (see measure.h).
#include "measure.h"

#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

namespace ohrp::identify {

// the sum of the comma-separated channels of `log` (e.g. both ankles' pitch moments); false
// with *error naming a missing one
bool Channel(const datalog::Table& log, const std::string& path, const std::string& channels,
             std::vector<double>* x, std::string* error) {
  std::stringstream ss(channels);
  x->assign(log.rows(), 0.0);
  int n = 0;
  for (std::string c; std::getline(ss, c, ',');) {
    const int col = log.Column(c);
    if (col < 0) {
      *error = path + ": no channel '" + c + "' (--channel)";
      return false;
    }
    for (size_t i = 0; i < x->size(); ++i) (*x)[i] += log.col(col)[i];
    ++n;
  }
  if (n == 0) {
    *error = "--channel names no channel";
    return false;
  }
  return true;
}

bool Measure(const datalog::Table& log, const std::string& path, const std::string& channel,
             double from, double to, Measured* m, std::string* error, double add_noise) {
  const int tc = log.Column("time");
  if (tc < 0) {
    *error = path + ": no column 'time'";
    return false;
  }
  m->t = log.col(tc);
  if (!Channel(log, path, channel, &m->x, error)) return false;
  m->osc = compare::AnalyseOscillation(m->t, m->x, from, to);
  if (!m->osc.found) {
    char buf[160];
    std::snprintf(buf, sizeof(buf), ": no damped oscillation of %s in [%.3f, %.3f] s: ",
                  channel.c_str(), from, to);
    *error = path + buf + m->osc.why;
    return false;
  }
  if (add_noise > 0) {
    // the recording's noise on the simulation too, so that both are measured alike (noise
    // biases the extrema of the small swings, hence the decay): the mean of kNoiseDraws
    // seeded draws
    constexpr int kNoiseDraws = 8;
    double f = 0, delta = 0;
    int used = 0;
    for (int k = 0; k < kNoiseDraws; ++k) {
      std::mt19937 rng(1000 + k);
      std::normal_distribution<double> n(0.0, add_noise);
      std::vector<double> x = m->x;
      for (double& v : x) v += n(rng);
      const compare::Oscillation o = compare::AnalyseOscillation(m->t, x, from, to);
      if (!o.found) continue;
      f += o.frequency;
      delta += o.log_decrement;
      ++used;
    }
    if (used == 0) {
      *error = path + ": with the recording's noise added, the oscillation of " + channel +
               " is not found any more";
      return false;
    }
    m->osc.frequency = f / used;
    m->osc.log_decrement = delta / used;
  }
  return true;
}

// the damping ratio of a log decrement (per period)
double ZetaOf(double delta) { return delta / std::sqrt(4 * M_PI * M_PI + delta * delta); }

// a least-squares line y = a + b x through the points; returns b and sets *a
double Line(const std::vector<double>& x, const std::vector<double>& y, double* a) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(x.size());
  my /= static_cast<double>(x.size());
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double b = sxy / sxx;
  *a = my - b * mx;
  return b;
}

}  // namespace ohrp::identify
