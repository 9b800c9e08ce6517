// Signal helpers of the log comparison (ohrp_compare_logs, ohrp identify): sampled series
// looked up in time, the time lag between two series by cross-correlation, the noise level of a
// series. Times in seconds; a series' times increase strictly.
#pragma once

#include <string>
#include <vector>

namespace ohrp::compare {

// The value of the series (t, x) at time `at` by linear interpolation, clamped to its ends.
// `cursor` (start at 0) is a row hint for monotone look-ups.
double Interpolate(const std::vector<double>& t, const std::vector<double>& x, double at,
                   size_t* cursor);

// The median step between successive times (0 with fewer than two times).
double MedianStep(const std::vector<double>& t);

// The lag of B behind A: the time shift `lag` that makes B(t + lag) best match A(t), found as
// the maximum of the cross-covariance sum over the overlap (each series less its mean),
// searched over |lag - around| <= max_lag on a grid of the coarser median step of the two, then
// refined between grid points by a parabola through the peak and its neighbours. The sum is
// not normalised by the overlap's length, so a periodic signal's neighbouring periods (a damped
// oscillation's smaller swings) do not tie with the true lag. False with `*error` when a series
// is flat, the peak lies on the edge of the search (raise max_lag), or the overlap is too short.
bool CrossCorrelationLag(const std::vector<double>& ta, const std::vector<double>& xa,
                         const std::vector<double>& tb, const std::vector<double>& xb,
                         double around, double max_lag, double* lag, std::string* error);

// The standard deviation of white noise on a smooth signal, from the median absolute second
// difference (a smooth signal sampled finely contributes almost nothing to it):
// sigma = MAD(x[i+1] - 2 x[i] + x[i-1]) / (0.6745 sqrt 6). 0 with fewer than 3 samples.
double NoiseSigma(const std::vector<double>& x, size_t begin = 0, size_t end = SIZE_MAX);

}  // namespace ohrp::compare
