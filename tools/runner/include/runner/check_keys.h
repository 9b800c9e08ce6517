// The check types of a scenario and the keys each one takes: one table, used to refuse a bad
// check when the scenario is read (an unknown type, an unknown or repeated key, a value of the
// wrong type or out of range, a time outside the run) and to write the table of
// docs/scenarios.md (CheckTableMarkdown; a test keeps the two equal), and the defaults of the
// numbers, which the evaluators read (CheckSpec::Number(key); checks.cc, sole_checks.cc).
#pragma once

#include <limits>
#include <string>
#include <vector>

namespace ohrp::runner {

enum class KeyKind {
  kNumber,  // a finite number in [lo, hi] (lo_open: lo excluded)
  kTime,    // a simulated time [s] within the run: [0, duration]
  kText,    // a single value (a sensor name)
  kList,    // a non-empty list of names (sensors)
  kBool,    // true or false
  kAxis,    // x, y or z
};

struct CheckKey {
  const char* name;
  KeyKind kind;
  bool required;
  const char* doc;   // unit and default as the docs show them, e.g. "m, 0.02"
  double lo = -1e300, hi = 1e300;
  bool lo_open = false;
  double fallback = std::numeric_limits<double>::quiet_NaN();  // a number's default (NaN: none,
                                                                // or one that depends on the run)
};

struct CheckType {
  const char* type;
  std::vector<CheckKey> keys;
  const char* passes_when;  // for the docs
};

// Every check type, in the order of the docs.
const std::vector<CheckType>& CheckTypes();

// The type named `type`, or null.
const CheckType* FindCheckType(const std::string& type);

// The default of number `key` of check `type` (CheckSpec::Number(key) uses it); NaN when the
// table has none.
double CheckDefault(const std::string& type, const std::string& key);

// "base_height, not_fallen, ..."
std::string CheckTypeNames();

// The markdown table of check types and their keys (docs/scenarios.md, section Checks).
std::string CheckTableMarkdown();

}  // namespace ohrp::runner
