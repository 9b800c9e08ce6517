// The control period (see period.h).
#include "sim_host/period.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::sim {

bool ChooseControlPeriod(double dt, double requested, double* period, int* steps_per_cycle,
                         std::string* error) {
  // the default: the multiple of the step nearest 5 ms (ties to the shorter period)
  if (requested <= 0) {
    const double ratio = kPreferredControlPeriod / dt;
    const int n = std::max(1, static_cast<int>(std::ceil(ratio - 0.5 - 1e-9)));
    *steps_per_cycle = n;
    *period = n * dt;
    return true;
  }
  // an explicit period: a whole number of steps, or the nearest ones that are
  const double ratio = requested / dt;
  const long n = std::lround(ratio);
  if (n >= 1 && std::fabs(ratio - n) <= 1e-6) {
    *steps_per_cycle = static_cast<int>(n);
    *period = requested;
    return true;
  }
  const long below = std::max(1L, static_cast<long>(std::floor(ratio)));
  const long above = std::max(below + 1, static_cast<long>(std::ceil(ratio)));
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "the control period (%g s) must be a whole multiple of the physics step (%g s): "
                "use --control-period %g or %g (or leave it out: %g s follows the step)",
                requested, dt, below * dt, above * dt,
                std::max(1.0, std::ceil(kPreferredControlPeriod / dt - 0.5 - 1e-9)) * dt);
  *error = buf;
  return false;
}

std::string DescribeControlPeriod(double dt, double period, int steps_per_cycle, bool defaulted) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "time:\n  physics step %g s, control period %g s (%d steps per cycle, %s)\n", dt,
                period, steps_per_cycle,
                defaulted ? "the multiple of the step nearest 5 ms" : "as asked by --control-period");
  return buf;
}

}  // namespace ohrp::sim
