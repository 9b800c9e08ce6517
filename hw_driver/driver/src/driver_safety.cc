// The driver's holds and stops (driver_loop.h): the safe mode, the servo-off damping, their end,
// and the boards' verification of each cycle with a valid read (board_checks.h).
#include "driver_loop.h"

namespace ohrp::hw {
namespace {

EventKind EventOf(CheckKind k) {
  switch (k) {
    case CheckKind::kImplausible: return EventKind::kImplausibleReading;
    case CheckKind::kServoMismatch: return EventKind::kServoMismatch;
    case CheckKind::kUnacknowledged: return EventKind::kCommandsUnacknowledged;
    case CheckKind::kTracking: return EventKind::kTrackingError;
    case CheckKind::kRefused: return EventKind::kCommandRefused;
    case CheckKind::kForeign: return EventKind::kForeignCommand;
    case CheckKind::kNone: break;
  }
  return EventKind::kImplausibleReading;
}

}  // namespace

void DriverLoop::EndResetHold() noexcept {
  reset_hold = false;
  for (int j = 0; j < d.njoint; ++j) d.joint_off[j] = false;
}

void DriverLoop::EnterSafeMode(int exit_code, const char* why, int64_t reason,
                               Rearm then) noexcept {
  EndResetHold();
  hold_cycles = 0;
  refused_in_hold = 0;
  d.state = DriverState::kSafeMode;
  after_safe_mode = then;
  d.guard.Damp(d.last_valid_q, o.safe_kp_scale, o.safe_kd_scale);
  phase_end = MonotonicNs() + std::llround(o.safe_time * 1e9);
  result_.safe_mode = true;
  result_.safe_mode_cycle = d.k;
  result_.exit_code = exit_code;
  outcome = why;
  d.Record(EventKind::kSafeMode, reason);
}

void DriverLoop::BeginStopping(int exit_code, const char* why) noexcept {
  result_.exit_code = exit_code;
  outcome = why;
  if (!d.servo_on) {
    done = true;
    return;
  }
  EndResetHold();
  hold_cycles = 0;
  refused_in_hold = 0;
  d.state = DriverState::kStopping;
  d.guard.Damp(d.last_valid_q, o.safe_kp_scale, o.safe_kd_scale);
  phase_end = MonotonicNs() + std::llround(o.servo_off_time * 1e9);
}

// The boards' verification of one cycle with a valid read (see board_checks.h): a board that
// disobeys ends the active state in a safe mode; a board refusing the hold of a safe mode or
// stop is a failure of its own; the IMU's tilt past fall_tilt is a fall.
void DriverLoop::CheckBoards() noexcept {
  if (d.state == DriverState::kActive && d.servo_on && !servoed_on) {
    bool skip[shm::kMaxJoints];
    for (int j = 0; j < d.njoint; ++j) skip[j] = reset_hold && d.rearm_joint[j];
    const Finding f = d.checks.Obeyed(d.in, d.commanded_on, d.guard.references(), skip);
    if (f.kind != CheckKind::kNone) {
      flags |= shm::status::kBoardFault;
      d.Record(EventOf(f.kind), f.joint < 0 ? static_cast<int64_t>(f.value) : 0, f.board,
               f.joint, f.value);
      detail = "a board did not do what it was commanded (see the events)";
      EnterSafeMode(kExitBoardDisobeys, "board_disobeys", kSafeBoardDisobeys, Rearm::kNone);
    }
  }
  if (d.state == DriverState::kSafeMode || d.state == DriverState::kStopping) CheckHoldObeyed();
  CheckFall();
}

void DriverLoop::CheckHoldObeyed() noexcept {
  ++hold_cycles;
  const uint32_t refused =
      (d.in.reports & io_report::kBoards) ? d.in.refused_boards & ~d.in.reset_boards : 0u;
  refused_in_hold = refused && hold_cycles > round_trip_cycles ? refused_in_hold + 1 : 0;
  if (refused_in_hold < round_trip_cycles || hold_refused) return;
  hold_refused = true;
  int b = 0;
  while (b < 31 && !(refused & (1u << b))) ++b;
  d.Record(EventKind::kSafeModeRefused, refused, b);
  if (result_.exit_code == kExitOk || result_.exit_code == kExitInterrupted) {
    result_.exit_code = kExitBoardDisobeys;
    outcome = "safe_mode_refused";
  }
  detail = "a board refused the damped hold: the robot was not held";
}

void DriverLoop::CheckFall() noexcept {
  if (o.fall_tilt <= 0 || !d.have_imu_reference || fell) return;
  if (d.state != DriverState::kActive && d.state != DriverState::kSafeMode &&
      d.state != DriverState::kStopping) {
    return;
  }
  const double tilt = TiltBetween(d.imu_reference, d.in.imu[0].quat_WI);
  if (tilt <= o.fall_tilt) return;
  fell = true;
  d.Record(EventKind::kFall, 0, -1, -1, tilt);
  detail = "the robot fell: its IMU tilted past --fall-tilt";
  if (d.state == DriverState::kActive) {
    EnterSafeMode(kExitFall, "fall", kSafeFall, Rearm::kNone);
  } else {
    result_.exit_code = kExitFall;
    outcome = "fall";
  }
}

//---- the end of a damped hold: servos off; the run ends, or waits to servo on again
void DriverLoop::EndOfHold() noexcept {
  if (d.state != DriverState::kSafeMode && d.state != DriverState::kStopping) return;
  if (MonotonicNs() < phase_end) return;
  d.servo_on = false;
  d.Record(EventKind::kServoOff);
  if (d.state == DriverState::kSafeMode && after_safe_mode != Rearm::kNone && stops_seen > 0) {
    // a stop asked for during a safe mode that would have recovered: the run ends here
    result_.exit_code = kExitInterrupted;
    outcome = "interrupted";
    done = true;
  } else if (d.state == DriverState::kSafeMode && after_safe_mode != Rearm::kNone) {
    // this servo-off is also the boards' re-arm after a reset (udp/PROTOCOL.md)
    d.state = DriverState::kInactive;
    rearm = after_safe_mode;
    clean_reads = 0;
    result_.exit_code = kExitOk;
    outcome = "completed";
    d.Record(rearm == Rearm::kBoards ? EventKind::kBoardRearm : EventKind::kWaitingForController);
  } else {
    done = true;
  }
}

}  // namespace ohrp::hw
