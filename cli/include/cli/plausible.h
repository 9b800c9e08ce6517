// The one table of plausible ranges (issue 28, item 6): every numeric option, file field and
// scenario key of every program names the quantity it is, and is checked against this table
// before anything runs. A value outside its range is refused with the quantity, the range, the
// unit and why the range is what it is, so that "1e308" or "1e-300" never reaches a simulation,
// a servo or a board.
//
// The ranges are wide: they bound what any humanoid of 0.5-3 m and 5-300 kg could want, not what
// HRP-1S uses. A range is about plausibility, not safety for one robot: a program that knows its
// robot narrows it further (a stride against the leg length, a gain against the servo's limit).
//
// Use, for a value read from anywhere (a file, a key, an option):
//   if (std::string e = ohrp::cli::CheckPlausible("physics_dt", dt, "scenario.yaml:12: physics_dt");
//       !e.empty()) { fprintf(stderr, "%s\n", e.c_str()); return 2; }
// and for a CLI11 option: `->check(ohrp::cli::Plausible("physics_dt"))` (command_line.h).
//
// Header-only, no dependency: the lower layers (robot_model, the bridge's users) may use it.
#pragma once

#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

namespace ohrp::cli {

struct PlausibleRange {
  const char* quantity;  // the name programs use, e.g. "physics_dt"
  double lo;             // smallest plausible value (inclusive)
  double hi;             // largest plausible value (inclusive)
  const char* unit;      // SI unit, "" for a pure number
  const char* why;       // what the bounds stand for, said with the refusal
};

// clang-format off
inline constexpr PlausibleRange kPlausibleRanges[] = {
  // time
  {"physics_dt",       1e-5,  0.02,  "s",     "an integration step between 10 us and 20 ms"},
  {"control_period",   1e-4,  0.1,   "s",     "a control cycle between 0.1 ms (10 kHz) and 100 ms"},
  {"duration",         1e-3,  1e6,   "s",     "a run between 1 ms and about 11 days"},
  {"timeout",          1e-3,  3600,  "s",     "a wait between 1 ms and an hour"},
  {"ramp_time",        0,     600,   "s",     "a ramp of at most 10 minutes (0: a jump)"},
  {"step_time",        0.2,   5,     "s",     "a walking step between 0.2 s and 5 s"},
  {"double_support",   0,     2,     "s",     "a double-support phase of at most 2 s"},
  {"push_duration",    1e-3,  5,     "s",     "a push lasting 1 ms to 5 s"},
  {"time",             -1e6,  1e6,   "s",     "a time within about 11 days of a run's start"},
  {"wait",             0,     3600,  "s",     "a wait or delay of at most an hour (0: none)"},
  {"time_constant",    1e-3,  100,   "s",     "a time constant between 1 ms and 100 s"},
  // gains and scales
  {"gain_scale",       0,     100,   "",      "a gain factor between 0 (limp) and 100x the default"},
  {"speed_factor",     1e-3,  1e3,   "",      "a playback or video speed between 0.001x and 1000x"},
  {"kp",               0,     1e6,   "N m/rad", "a joint stiffness of at most 1e6 N m/rad"},
  {"kd",               0,     1e4,   "N m s/rad", "a joint damping of at most 1e4 N m s/rad"},
  {"hold_gain_scale",  1e-2,  100,   "",      "a holding gain factor between 0.01 (soft, still holding) and 100x the default"},
  {"rate",             0,     1e3,   "1/s",   "a convergence rate (a gain per second) of at most 1000/s"},
  {"rate2",            0,     1e4,   "1/s^2", "an integral gain of at most 1e4/s^2"},
  {"linear_damping",   0,     1e7,   "N s/m", "a translational damping of at most 1e7 N s/m"},
  // contact
  {"sole_stiffness",   1e2,   1e9,   "N/m",   "a sole stiffness between a sponge (1e2) and steel on steel (1e9)"},
  {"sole_damping",     0,     1e7,   "N s/m", "a sole damping of at most 1e7 N s/m"},
  {"friction",         0,     10,    "",      "a friction coefficient between 0 and 10"},
  // geometry of walking and standing
  {"stride",           0,     1.5,   "m",     "a step length of at most 1.5 m"},
  {"step_height",      0,     0.5,   "m",     "a change of ground height of at most 0.5 m per step"},
  {"swing_apex",       0,     0.5,   "m",     "a swing foot lifted at most 0.5 m"},
  {"support_margin",   0,     0.2,   "m",     "a margin inside the support polygon of at most 20 cm"},
  {"height",           -10,   10,    "m",     "a height within 10 m of the ground"},
  {"distance",         0,     1e3,   "m",     "a distance of at most 1 km"},
  {"angle",            -7,    7,     "rad",   "an angle within about one turn"},
  {"slope",            0,     0.8,   "rad",   "a slope of at most about 45 deg"},
  {"speed",            0,     5,     "m/s",   "a walking speed of at most 5 m/s"},
  {"yaw_rate",         0,     6.3,   "rad/s", "a turning rate of at most one turn a second"},
  {"joint_speed",      0,     100,   "rad/s", "a joint speed of at most 100 rad/s"},
  {"angle_deg",        -360,  360,   "deg",   "an angle within one turn"},
  {"clearance",        0,     0.5,   "m",     "a distance kept between links of at most 50 cm"},
  {"tilt",             0,     3.1416, "rad",  "a tilt between 0 and half a turn"},
  {"body_offset",      -2,    2,     "m",     "a point within 2 m of its body's origin"},
  {"sole_size",        1e-3,  1,     "m",     "a sole side (or thickness) between 1 mm and 1 m"},
  // loads
  {"impulse",          0,     1e3,   "N s",   "a push of at most 1000 N s"},
  {"force",            0,     1e5,   "N",     "a force of at most 1e5 N"},
  {"torque",           0,     1e5,   "N m",   "a torque of at most 1e5 N m"},
  {"mass",             1e-3,  1e4,   "kg",    "a mass between 1 g and 10 t"},
  // counts and sizes
  {"count",            0,     1e9,   "",      "a count of at most a billion"},
  {"steps",            1,     1e9,   "",      "a number of steps between 1 and a billion"},
  {"cycles",           1,     1e9,   "",      "a number of cycles between 1 and a billion"},
  {"bytes",            1,     1e13,  "B",     "a size of at most 10 TB"},
  {"fraction",         0,     1,     "",      "a fraction between 0 and 1"},
  {"noise",            0,     10,    "",      "a noise level (in the signal's unit) of at most 10"},
  {"frequency",        1e-3,  1e5,   "Hz",    "a frequency between 1 mHz and 100 kHz"},
  {"repeats",          1,     1e6,   "",      "a number of repetitions (rounds, restarts, windows) between 1 and a million"},
  {"frames",           1,     1e7,   "",      "a video of at most 10 million frames (about 4 days at 30 fps)"},
  {"samples",          2,     1e8,   "",      "a signal of 2 to 1e8 samples (at most 0.8 GB as doubles)"},
  {"pixels",           16,    4096,  "px",    "an image side of 16 to 4096 pixels"},
  {"frame_rate",       1,     240,   "Hz",    "1 to 240 frames a second"},
  {"port",             0,     65535, "",      "a TCP or UDP port number (0: the system picks a free one)"},
  {"priority",         0,     99,    "",      "a SCHED_FIFO priority of 1 to 99 (0: SCHED_OTHER)"},
};
// clang-format on

// The range of `quantity`, or nullptr when the table has no such quantity (a programming error:
// the tests check that every name a program uses is in the table).
inline const PlausibleRange* FindPlausible(std::string_view quantity) {
  for (const PlausibleRange& r : kPlausibleRanges) {
    if (quantity == r.quantity) return &r;
  }
  return nullptr;
}

namespace detail {
inline std::string PlausibleNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}
}  // namespace detail

// "the plausible range [LO, HI] UNIT (WHY)" of `r`, for messages
inline std::string PlausibleRangeText(const PlausibleRange& r) {
  // appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "literal" + temporary string
  std::string text = "the plausible range [";
  text += detail::PlausibleNumber(r.lo);
  text += ", ";
  text += detail::PlausibleNumber(r.hi);
  text += "]";
  if (r.unit[0]) (text += " ") += r.unit;
  return (((text += " (") += r.why) += ")");
}

// true when `value` is finite and within `r` (bounds inclusive)
inline bool IsPlausible(const PlausibleRange& r, double value) {
  return std::isfinite(value) && value >= r.lo && value <= r.hi;
}

// "" when `value` is finite and within the plausible range of `quantity`; otherwise one sentence:
// "WHERE = VALUE is outside the plausible range [LO, HI] UNIT (WHY)". `where` names the value
// for the user: "--kp-scale", "walk.yaml:4: step_time", "scenario key physics_dt".
inline std::string CheckPlausible(std::string_view quantity, double value, std::string_view where) {
  const PlausibleRange* r = FindPlausible(quantity);
  std::string w(where);
  if (r == nullptr) return w + ": no plausible range for the quantity '" + std::string(quantity) + "'";
  if (IsPlausible(*r, value)) return std::string();
  return w + " = " + detail::PlausibleNumber(value) + " is outside " + PlausibleRangeText(*r);
}

// "" when every value of `values` (a column of a log, the entries of a list) is plausible as
// `quantity`; otherwise the sentence of CheckPlausible for the first that is not, its place
// named "WHERE, row N" (N counted from 1).
template <typename Values>
inline std::string CheckPlausibleEach(std::string_view quantity, const Values& values,
                                      std::string_view where) {
  const PlausibleRange* r = FindPlausible(quantity);
  size_t row = 0;
  for (const double v : values) {
    ++row;
    if (r == nullptr || !IsPlausible(*r, v))
      return CheckPlausible(quantity, v, std::string(where) + ", row " + std::to_string(row));
  }
  return std::string();
}

}  // namespace ohrp::cli
