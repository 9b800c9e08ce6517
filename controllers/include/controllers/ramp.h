// A smooth move from one pose to another: the minimum-jerk profile.
//
//   s(u) = 10 u^3 - 15 u^4 + 6 u^5,   u = elapsed / duration clamped to [0, 1]
//   q(t) = q_from + (q_to - q_from) s(u),   dq(t) = (q_to - q_from) s'(u) / duration
// s is monotone on [0, 1], starts and ends with zero velocity and zero acceleration.
// Time is whatever clock the caller passes (the controllers pass the producer's `time`).
#pragma once

namespace ohrp::controllers {

// s(u) for u clamped to [0, 1].
double MinimumJerk(double u) noexcept;
// ds/du for u clamped to [0, 1] (0 outside).
double MinimumJerkRate(double u) noexcept;

// Fills q[0..n) and dq[0..n) (dq may be null) with the ramp from `from` to `to` at `elapsed`
// [s] of a `duration` [s] ramp. duration <= 0 means an immediate jump (q = to, dq = 0).
// Never allocates; arrays may not overlap.
void SampleRamp(const double* from, const double* to, int n, double elapsed, double duration,
                double* q, double* dq) noexcept;

}  // namespace ohrp::controllers
