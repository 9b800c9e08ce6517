// How much the recording's noise alone moves the measured oscillation (see noise_spread.h).
#include "noise_spread.h"

#include <cmath>
#include <random>

#include "compare/oscillation.h"

namespace ohrp::identify {

Spread NoiseSpread(const std::vector<double>& t, const std::vector<double>& x, double from, double to,
                   double noise, int draws) {
  Spread s;
  if (!(noise > 0)) return s;
  double sf = 0, sf2 = 0, sd = 0, sd2 = 0;
  for (int k = 0; k < draws; ++k) {
    std::mt19937 rng(7000 + k);  // other seeds than the simulations' noise (simulate: 1000 + k)
    std::normal_distribution<double> n(0.0, noise);
    std::vector<double> y = x;
    for (double& v : y) v += n(rng);
    const compare::Oscillation o = compare::AnalyseOscillation(t, y, from, to);
    if (!o.found) continue;
    ++s.measured;
    sf += o.frequency;
    sf2 += o.frequency * o.frequency;
    sd += o.log_decrement;
    sd2 += o.log_decrement * o.log_decrement;
  }
  if (s.measured < 2) return s;
  const double m = s.measured;
  s.f_sd = std::sqrt(std::max(0.0, (sf2 - sf * sf / m) / (m - 1)));
  s.delta_sd = std::sqrt(std::max(0.0, (sd2 - sd * sd / m) / (m - 1)));
  return s;
}

}  // namespace ohrp::identify
