// How much the recording's noise alone moves the measured oscillation (issue 35: the stated
// uncertainties were the measurement's standard errors, 5-40 times smaller than the errors seen):
// the simulated channel at the identified soles, which matches the recording, gets `draws`
// seeded draws of the recording's noise (1 sigma `noise`) and is measured each time as the
// recording is (compare/oscillation.h over [from, to]); the spread (standard deviation) of the
// frequency and the log decrement over the draws is what one recording can tell.
#pragma once

#include <vector>

namespace ohrp::identify {

struct Spread {
  double f_sd = 0, delta_sd = 0;  // [Hz], [-]
  int measured = 0;               // draws whose oscillation was found
};

Spread NoiseSpread(const std::vector<double>& t, const std::vector<double>& x, double from, double to,
                   double noise, int draws = 40);

}  // namespace ohrp::identify
