// Names of the set-up errors.
#include "controllers/config_status.h"

namespace ohrp::controllers {

const char* ConfigErrorName(ConfigError e) {
  switch (e) {
    case ConfigError::kOk: return "ok";
    case ConfigError::kFile: return "file";
    case ConfigError::kSyntax: return "syntax";
    case ConfigError::kColumns: return "columns";
    case ConfigError::kNonFinite: return "non-finite";
    case ConfigError::kTime: return "time";
    case ConfigError::kEmpty: return "empty";
    case ConfigError::kUnknownJoint: return "unknown-joint";
    case ConfigError::kMismatch: return "mismatch";
    case ConfigError::kLimits: return "limits";
    case ConfigError::kOption: return "option";
    case ConfigError::kState: return "state";
  }
  return "?";
}

}  // namespace ohrp::controllers
