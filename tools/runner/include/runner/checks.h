// Pass criteria of a scenario, evaluated on sim_host's data log (CSV, see
// sim_host/recorder.h) and its JSON summary.
//
// Check types (keys beyond `type`; times are simulated seconds, lengths metres):
//   base_height        after, [until], tolerance, [reference]: the base height stays within
//                      `tolerance` of `reference` (default: its mean over the window)
//   not_fallen         [min_height = 0.4], [max_tilt_deg = 45]: over the whole run
//   feet_carry_weight  after, [until], sensors (list), tolerance (relative): the mean of the sum
//                      of the sensors' vertical forces equals the weight they carry (the robot's
//                      mass less the mass below each sensor, times g)
//   base_displacement  axis (x | y | z), [min], [max], [from = 0]: base position at the end
//                      minus at `from`
//   force_ringing      after, [until], sensors (list), [window = 0.02], max [N]: the RMS of each
//                      sensor's vertical force less its moving average over `window` (its
//                      high-frequency content), the largest over the sensors
//   standing           stance_at, after, [min_height_fraction = 0.8], [max_tilt_deg = 30],
//                      [sensors], [load_tolerance = 0.1]: still standing after a push
//                      (runner/recovery.h, StandingSpec)
//   settles            at, [duration = 0.1], [tolerance = 0.01], [fraction = 0.1], [within = 1],
//                      [baseline = 0.5], [sensors = rfsensor, lfsensor]: after the push on
//                      [at, at + duration] the base and the ankle torques settle (SettleSpec)
//   cop_inside         after, [until], [sensors = every sensor with a sole], [margin = 0.01],
//                      [min_fz = 50], [require_loaded = false]: at every row each sole carrying
//                      at least min_fz has its centre of pressure `margin` inside its edges (a
//                      lighter sole is lifted and not judged, or fails with require_loaded); the
//                      value is the smallest distance inside (runner/sole_checks.h)
//   foot_lifted        sensor, after, until, [max_fz = 10]: the sensor's vertical force stays
//                      below max_fz [N] over the window (the foot is in the air)
//   max_rejected       [max = 0]: joint commands rejected by the servo over the run
//   real_time_factor   min: simulated over wall time of sim_host
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "runner/scenario.h"

namespace ohrp::runner {

// A CSV file read column by column.
class Table {
 public:
  bool Load(const std::string& path, std::string* error);
  int Column(const std::string& name) const;  // -1 when absent
  const std::vector<double>& col(int c) const { return cols_[c]; }
  size_t rows() const { return cols_.empty() ? 0 : cols_[0].size(); }
  const std::vector<std::string>& names() const { return names_; }

 private:
  std::vector<std::string> names_;
  std::vector<std::vector<double>> cols_;
};

struct CheckResult {
  std::string name;     // type, plus a label where useful
  bool passed = false;
  double value = 0;     // the measured figure
  std::string unit;
  std::string limit;    // what it was compared with, readable
  std::string detail;   // why it failed, or what was measured
};

// Evaluates one check. `sim` is sim_host's summary (robot_mass, gravity, mass_below, ...).
CheckResult Evaluate(const CheckSpec& spec, const Table& log, const nlohmann::json& sim);

}  // namespace ohrp::runner
