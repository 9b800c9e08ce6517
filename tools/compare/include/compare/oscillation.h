// The frequency and decay of a damped oscillation in a sampled channel, as the paper's figure
// 12 shows them (the standing robot rocking on its soft soles after a push).
//
// Method: the extrema of the channel within [from, to] are found with a hysteresis (a swing
// counts once the signal has come back from it by more than max(6 noise sigma, 2 % of the
// window's range), so noise makes no extrema), each refined by a least-squares parabola over
// its neighbourhood. For x(t) = c + A exp(-sigma t) sin(omega t + phi) the extrema are exactly
// half a damped period apart and the swing between two successive ones,
// h_i = |e_{i+1} - e_i|, falls as exp(-sigma t_i), whatever the offset c. So:
//   damped period T_d = 2 x slope of the extremum times against their index (least squares),
//   sigma = -slope of ln h_i against time (least squares, each ln h_i weighted by its inverse
//   variance (sqrt(2) noise / h_i)^2 with a 1 % floor, so that the tail's swings near the
//   noise, which one draw of noise keeps and another drops, hardly move it; swings are kept
//   while above 16 noise sigma),
//   log decrement delta = sigma T_d (per period), decay ratio exp(-delta) (amplitude ratio of
//   one period to the previous), damping ratio zeta = delta / sqrt(4 pi^2 + delta^2), natural
//   frequency f_n = f_d / sqrt(1 - zeta^2).
// The standard errors come from the two fits' residuals. At least 4 extrema are needed; with 1
// to 3 (an oscillation damped so heavily that fewer swings stand above the noise) a damped sine
// is fitted to the window instead (damped_fit.h; `method` "fit"), started from their spacing
// and ratio, and accepted when it converges decaying and explains at least half the signal.
#pragma once

#include <string>
#include <vector>

namespace ohrp::compare {

struct Oscillation {
  bool found = false;
  std::string why;               // when not found: what was missing
  std::string method = "extrema";  // or "fit": a damped sine fitted (heavily damped)
  int extrema = 0;               // used in the fits
  double first = 0, last = 0;    // [s] times of the first and last extremum used
  double frequency = 0;          // damped frequency f_d [Hz]
  double frequency_se = 0;       // its standard error [Hz]
  double natural_frequency = 0;  // f_n [Hz]
  double sigma = 0;              // decay rate of the envelope [1/s]
  double sigma_se = 0;
  double log_decrement = 0;      // delta = sigma T_d
  double log_decrement_se = 0;
  double decay_ratio = 0;        // exp(-delta): amplitude after one period / before
  double damping_ratio = 0;      // zeta
  double amplitude = 0;          // first swing h_0 / 2
  double noise = 0;              // noise sigma of the window (signal.h NoiseSigma)
  std::vector<double> extremum_times, extremum_values;  // those used
};

Oscillation AnalyseOscillation(const std::vector<double>& t, const std::vector<double>& x,
                               double from, double to);

}  // namespace ohrp::compare
