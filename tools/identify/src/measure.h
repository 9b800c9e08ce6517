// ohrp identify's measurements (identify.cc): a data log's channel (the sum of comma-separated
// columns), its damped oscillation over a window (compare/oscillation.h, optionally with the
// recording's noise added), and the damping ratio and least-squares lines of the refinement.
#pragma once

#include <string>
#include <vector>

#include "compare/oscillation.h"
#include "datalog/table.h"

namespace ohrp::identify {

struct Measured {
  compare::Oscillation osc;
  std::vector<double> t, x;
};

// the sum of the comma-separated channels of `log` (e.g. both ankles' pitch moments); false
// with *error naming a missing one
bool Channel(const datalog::Table& log, const std::string& path, const std::string& channels,
             std::vector<double>* x, std::string* error);

// the oscillation of `channel` over [from, to] [s]; with add_noise > 0 (1 sigma), its frequency
// and log decrement are the mean over seeded draws of that noise added; false with *error
bool Measure(const datalog::Table& log, const std::string& path, const std::string& channel,
             double from, double to, Measured* m, std::string* error, double add_noise = 0);

// the damping ratio of a log decrement (per period)
double ZetaOf(double delta);

// a least-squares line y = a + b x through the points; returns b and sets *a
double Line(const std::vector<double>& x, const std::vector<double>& y, double* a);

}  // namespace ohrp::identify
