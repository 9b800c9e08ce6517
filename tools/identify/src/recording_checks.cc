// Does the recording hold the experiment? (recording_checks.h)
#include "recording_checks.h"

#include <algorithm>
#include <cstdio>

#include "compare/signal.h"

namespace ohrp::identify {

bool CheckTimeBase(const std::vector<double>& t, double from, double to, double max_gap,
                   const std::string& path, std::string* error) {
  const double h = compare::MedianStep(t);
  if (!(h > 0)) return true;  // the loader refused non-increasing times already
  size_t worst = 0;
  double worst_step = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    if (t[i] < from || t[i - 1] > to) continue;
    const double step = t[i] - t[i - 1];
    if (step > worst_step) {
      worst_step = step;
      worst = i;
    }
  }
  if (worst_step <= max_gap) return true;
  char buf[500];
  std::snprintf(buf, sizeof(buf),
                "%s: the time base has a gap of %.4g s (the median step is %.4g s) at t = %.4f s, inside "
                "the experiment's span [%.3f, %.3f] s, longer than %.4g s (a tenth of the oscillation's "
                "period): rows missing there (an emulator that resynchronised to the wall clock, a "
                "driver that stopped); the oscillation cannot be measured across it: record the "
                "experiment again",
                path.c_str(), worst_step, h, t[worst - 1], from, to, max_gap);
  *error = buf;
  return false;
}

bool CheckSwing(double recorded, double simulated, double from, double to, const std::string& path,
                std::string* error) {
  if (!(simulated > 0) || (recorded <= kSwingFactor * simulated && recorded * kSwingFactor >= simulated))
    return true;
  char buf[400];
  std::snprintf(buf, sizeof(buf),
                "%s: its first swing in the window [%.3f, %.3f] s is %.3g, the simulated experiment's "
                "%.3g (%.2gx): not the scenario's push at the scenario's time (a push that came "
                "earlier leaves only its decayed tail in the window); check the recording and "
                "the scenario",
                path.c_str(), from, to, recorded, simulated, recorded / simulated);
  *error = buf;
  return false;
}

}  // namespace ohrp::identify
