// Errors of the controllers' set-up steps (loading files, matching them to the robot).
//
// Set-up can fail and says exactly what failed: a code for programs and tests, and a sentence
// for the user that names the file and line (or the joint) and what to do. The per-cycle path
// never produces a ConfigStatus: it counts problems instead (see controller.h).
#pragma once

#include <string>

namespace ohrp::controllers {

enum class ConfigError {
  kOk = 0,
  kFile,          // a file could not be opened or read
  kSyntax,        // a token is not a number / the YAML is malformed / a key is misplaced
  kColumns,       // a row has the wrong number of columns
  kNonFinite,     // a value is NaN or infinite
  kTime,          // the time column is not strictly increasing
  kEmpty,         // a file holds no data rows
  kUnknownJoint,  // a pose names a joint the robot does not have
  kMismatch,      // a file does not fit the robot (joint count) or its companion file
  kLimits,        // a target lies outside the robot's joint limits
  kOption,        // an option value is out of its range (e.g. a negative ramp)
  kState,         // a lifecycle transition was asked in the wrong state
};

const char* ConfigErrorName(ConfigError e);

// Outcome of a set-up call: a code and a message for the user.
struct ConfigStatus {
  ConfigError code = ConfigError::kOk;
  std::string message;
  bool ok() const { return code == ConfigError::kOk; }
  static ConfigStatus Ok() { return {}; }
  static ConfigStatus Fail(ConfigError code, std::string message) {
    return {code, std::move(message)};
  }
};

}  // namespace ohrp::controllers
