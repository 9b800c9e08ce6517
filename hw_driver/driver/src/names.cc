// The names of the driver's states and events, as the report and the summary print them
// (see driver.h).
#include "hw_driver/driver.h"

namespace ohrp::hw {

const char* DriverStateName(DriverState s) {
  switch (s) {
    case DriverState::kUnconfigured: return "unconfigured";
    case DriverState::kInactive: return "inactive";
    case DriverState::kActive: return "active";
    case DriverState::kSafeMode: return "safe_mode";
    case DriverState::kStopping: return "stopping";
    case DriverState::kClosed: return "closed";
  }
  return "?";
}

const char* EventName(EventKind k) {
  switch (k) {
    case EventKind::kServoOn: return "servo_on";
    case EventKind::kControllerAttached: return "controller_attached";
    case EventKind::kControllerSilent: return "controller_silent";
    case EventKind::kControllerDied: return "controller_died";
    case EventKind::kControllerDetached: return "controller_detached";
    case EventKind::kBoardSilent: return "board_silent";
    case EventKind::kBoardBack: return "board_back";
    case EventKind::kBoardReset: return "board_reset";
    case EventKind::kSensorFault: return "sensor_fault";
    case EventKind::kSafeMode: return "safe_mode";
    case EventKind::kServoOff: return "servo_off";
    case EventKind::kEmergencyStop: return "emergency_stop";
    case EventKind::kEndOfData: return "end_of_data";
    case EventKind::kStopRequested: return "stop_requested";
    case EventKind::kDurationReached: return "duration_reached";
    case EventKind::kIoError: return "io_error";
    case EventKind::kNoValidRead: return "no_valid_read";
    case EventKind::kBoardNonFinite: return "board_non_finite";
    case EventKind::kWaitingForController: return "waiting_for_controller";
    case EventKind::kBoardRearm: return "board_rearm";
    case EventKind::kImplausibleReading: return "implausible_reading";
    case EventKind::kServoMismatch: return "servo_mismatch";
    case EventKind::kCommandsUnacknowledged: return "commands_unacknowledged";
    case EventKind::kTrackingError: return "tracking_error";
    case EventKind::kCommandRefused: return "command_refused";
    case EventKind::kForeignCommand: return "foreign_command";
    case EventKind::kSafeModeRefused: return "safe_mode_refused";
    case EventKind::kResetHold: return "reset_hold";
    case EventKind::kResetRamped: return "reset_ramped";
    case EventKind::kGuardHoldBegin: return "guard_hold_begin";
    case EventKind::kGuardHoldEnd: return "guard_hold_end";
    case EventKind::kFall: return "fall";
  }
  return "?";
}

}  // namespace ohrp::hw
