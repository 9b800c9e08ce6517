// printf's "%.9g" text of a double, several times faster than snprintf and about twice as fast
// as std::to_chars(general, 9): the producers' data log (recorder.h) formats a row of about 130
// numbers each control cycle on a writer thread that shares the machine's CPUs with a lock-step
// run, so what it costs is taken from the simulation.
//
// The text is exactly printf's in the "C" locale (the same digits, the same choice between
// fixed and exponent notation, trailing zeros removed, "-0", "nan", "-nan", "inf"): nine
// significant digits from one scaled product, with the exact path (std::to_chars) for the
// values it cannot round with certainty (within 1e-5 of a rounding tie), for subnormals and
// the largest exponents, and for NaN and the infinities. tests/robot_model/format_g9_test.cc
// compares it with snprintf on millions of values.
#pragma once

namespace ohrp::datalog {

// writes the text at `out` (no terminating NUL) and returns its end; `out` must have room for
// kFormatG9Max characters
inline constexpr int kFormatG9Max = 24;
char* FormatG9(char* out, double v);

}  // namespace ohrp::datalog
