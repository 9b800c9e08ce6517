// The control period of a run: the sensor/command cycle is a whole number of physics steps.
// By default it follows the scene's step (the multiple of it nearest HRP-1S's 5 ms); a period
// asked for explicitly must be a multiple of the step, else the error names the ones that are.
#pragma once

#include <string>

namespace ohrp::sim {

inline constexpr double kPreferredControlPeriod = 0.005;  // [s], HRP-1S's cycle

// Chooses the control period for physics step `dt` [s] (> 0). `requested` [s]: 0 for the
// default (n dt with n >= 1 the integer nearest kPreferredControlPeriod / dt, the smaller on a
// tie), else a period that must be n dt for an integer n >= 1 (to 1e-6 of a step). Returns false
// with `*error` saying why and naming the two multiples of `dt` nearest `requested`.
bool ChooseControlPeriod(double dt, double requested, double* period, int* steps_per_cycle,
                         std::string* error);

// The lines of `sim_host --explain` about time: the step, the period, how many steps per cycle,
// and whether the period was chosen from the step (`defaulted`) or asked for.
std::string DescribeControlPeriod(double dt, double period, int steps_per_cycle, bool defaulted);

}  // namespace ohrp::sim
