// Push recovery measured on sim_host's data log (see sim_host/recorder.h): is the robot still
// standing after a push, and how long do its base and its ankle torques take to settle. The
// scenario checks `standing` and `settles` (checks.h) and the push tool (tools/push/) use these.
// SI units: times in simulated seconds, lengths in metres, torques in N m.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "runner/checks.h"

namespace ohrp::runner {

// "Still standing" after a push starting at `stance_at`:
//   - the stance height h0 is the mean base height (base_z) over [stance_at - 0.2, stance_at];
//   - from `after` to the end of the log the base stays above `min_height_fraction` * h0 and
//     the base's z axis stays within `max_tilt_deg` of the vertical;
//   - the log reaches `after` (a run cut short is not standing);
//   - with `sensors` (ankle F/T sites) and a sim_host summary: the mean of the sensors' summed
//     vertical force over [after, end] is within `load_tolerance` (relative) of the weight above
//     them, i.e. the feet, not a knee or a hand, carry the robot.
struct StandingSpec {
  double stance_at = 0;             // [s] e.g. the push's start
  double after = 0;                 // [s] e.g. the push's end + 3 s
  double min_height_fraction = 0.8;
  double max_tilt_deg = 30;         // [deg]
  std::vector<std::string> sensors; // empty: no load test
  double load_tolerance = 0.1;      // relative
};

struct StandingResult {
  bool standing = false;
  double stance_height = 0;  // [m] h0
  double lowest_height = 0;  // [m] from `after` on
  double largest_tilt = 0;   // [deg] from `after` on
  double load_ratio = 0;     // mean summed fz / weight above the sensors (0 when not tested)
  std::string why;           // what failed, or a readable summary
};

// Returns false with `*error` when the log lacks the columns or the data the spec needs (a
// log that ends before `after` is a valid answer: not standing).
bool MeasureStanding(const datalog::Table& log, const nlohmann::json& sim, const StandingSpec& spec,
                     StandingResult* out, std::string* error);

// Settling after a push on [at, at + duration]:
//   - base: the stance is the mean horizontal base position (base_x, base_y) over the
//     `baseline` seconds before `at`; the base has settled at the first time after the push's
//     end from which its horizontal distance to the stance stays within `tolerance` to the end
//     of the log;
//   - ankle torques: for each sensor the pitch and roll torques (<s>_tx, <s>_ty, sensor frame)
//     less their mean over the same baseline window; e(t) is the Euclidean norm of these
//     deviations over all sensors; its first peak P is the largest e(t) from `at` on (the push
//     drives the largest deviation; the oscillation that follows decays from it); the envelope
//     is E(t) = max of e over [t, end of log]; the torques have settled at the first time after
//     the push's end at which E(t) < `fraction` * P.
// Times are reported from the push's end (0 when already within the bound then); a quantity
// still outside its bound at the log's last sample gets +infinity. `settled` is true when both
// times are <= `within`.
struct SettleSpec {
  double at = 0;           // [s] push start
  double duration = 0.1;   // [s]
  double baseline = 0.5;   // [s] before `at`
  double tolerance = 0.01; // [m]
  double fraction = 0.1;
  double within = 1.0;     // [s]
  std::vector<std::string> sensors = {"rfsensor", "lfsensor"};
};

struct SettleResult {
  bool settled = false;
  double base_time = 0;       // [s] after the push's end
  double torque_time = 0;     // [s] after the push's end
  double first_peak = 0;      // [N m] P
  double base_excursion = 0;  // [m] largest horizontal distance to the stance after `at`
};

// Returns false with `*error` when the log lacks the columns, the baseline or the push.
bool MeasureSettling(const datalog::Table& log, const SettleSpec& spec, SettleResult* out, std::string* error);

}  // namespace ohrp::runner
