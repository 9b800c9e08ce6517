// Pass criteria of a scenario, evaluated on sim_host's data log (CSV, see
// sim_host/recorder.h) and its JSON summary.
//
// The check types and the keys each takes are one table, runner/check_keys.h (which the
// scenario parser checks entries against and docs/scenarios.md shows), with the defaults of
// the numbers, which Evaluate reads through CheckSpec::Number(key).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "datalog/table.h"
#include "runner/scenario.h"

namespace ohrp::runner {

struct CheckResult {
  std::string name;     // type, plus a label where useful
  bool passed = false;
  double value = 0;     // the measured figure
  std::string unit;
  std::string limit;    // what it was compared with, readable
  std::string detail;   // why it failed, or what was measured
};

// The items of a check's list parameter (stored joined with ',', see check_parse.h).
std::vector<std::string> SplitList(const std::string& s);

// Evaluates one check. `sim` is sim_host's summary (robot_mass, gravity, mass_below, ...).
CheckResult Evaluate(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim);

}  // namespace ohrp::runner
