// The driver's real-time cycle (driver_loop.h): wait for the slot, read the boards, the faults
// and servo-on, publish the sensors, take the controller's commands, write the boards.
#include "driver_loop.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "requests.h"

namespace ohrp::hw {
namespace {

// how long a board may take to show what it was last written (a round trip and a board cycle;
// up to 11 ms measured on a loaded machine), and to clear its reset flag after the re-arm
constexpr double kRoundTripTime = 0.02;  // [s]
constexpr double kRearmTime = 0.1;       // [s]

int CyclesOf(double seconds, double period) {
  return static_cast<int>(std::ceil(seconds / std::max(period, 1e-6)));
}

}  // namespace

DriverLoop::DriverLoop(Driver::Impl& impl, DriverResult& result, LiveStats& live)
    : d(impl),
      o(impl.opt),
      result_(result),
      live_(live),
      period(PeriodNs(o)),
      window(std::llround(static_cast<double>(period) *
                          (1.0 - std::clamp(o.command_margin, 0.0, 0.9)))),
      servo_on_timeout(std::llround(o.servo_on_timeout * 1e9)),
      on_loss(o.on_controller_loss == shm::ControllerLoss::kWait ? Rearm::kController
                                                                 : Rearm::kNone),
      t0(MonotonicNs()),
      ramp_ns(std::max<int64_t>(1, std::llround(o.reset_ramp_time * 1e9))),
      round_trip_cycles(std::max(2, CyclesOf(kRoundTripTime, o.period))),
      rearm_cycles(std::max(o.board_timeout_cycles, CyclesOf(kRearmTime, o.period))),
      slot(t0),
      silent_reason(kSafeBoardSilent) {}

bool DriverLoop::Cycle() noexcept {
  WaitForSlot();
  flags = 0;
  servoed_on = false;
  ReadBoards();
  EmergencyStop();
  if (!done) FaultsAndServoOn();
  if (!done && !silent) CheckBoards();
  Sensors();
  if (!done && d.state == DriverState::kActive && !servoed_on) Commands();
  if (!done) EndOfHold();

  //---- write the boards
  d.Write();
  if (MonotonicNs() > slot + period) Bump(live_.deadline_misses);
  live_.cycles.store(d.k + 1, std::memory_order_relaxed);
  live_.state.store(static_cast<uint32_t>(d.state), std::memory_order_relaxed);
  if (done) return false;

  StopsAndDuration();
  if (done) return false;
  NextSlot();
  return true;
}

void DriverLoop::WaitForSlot() noexcept {
  d.time = static_cast<double>(slot - t0) * 1e-9;
  if (d.k == 0) return;
  live_.lateness.Add(d.waker.WaitUntil(slot) - slot);
  live_.spin_ns.store(d.waker.spin_ns(), std::memory_order_relaxed);
  live_.wake_margin_ns.store(d.waker.margin_ns(), std::memory_order_relaxed);
}

//---- read the boards
void DriverLoop::ReadBoards() noexcept {
  const IoResult r = d.io->read(&d.in);
  faults = r == IoResult::kError ? 0u : d.in.faults;
  live_.packets_lost.store(d.in.packets_lost, std::memory_order_relaxed);
  // a NaN or inf from a board is no valid read either, but named as what it is; so is a
  // reading no joint can give (board_checks.h: outside the range's margin, too fast)
  const bool nonfinite = (faults & io_fault::kNonFinite) || !AllFinite(d.in.q, d.njoint);
  const bool no_answer = r == IoResult::kError || (faults & io_fault::kBoardSilent);
  const Finding implausible = no_answer ? Finding{} : d.checks.Plausible(d.in);
  const bool bad_values = nonfinite || implausible.kind != CheckKind::kNone;
  silent = no_answer || bad_values;
  if (silent) {
    Bump(live_.silent_reads);
    ++silent_board;
    flags |= shm::status::kBoardFault;
    if (!board_was_silent) RecordSilentRead(r == IoResult::kError, no_answer, nonfinite, implausible);
  } else {
    std::memcpy(d.last_valid_q, d.in.q, d.njoint * sizeof(double));
    if (board_was_silent) d.Record(EventKind::kBoardBack, silent_board);
    silent_board = 0;
  }
  board_was_silent = silent;
  if (faults & (io_fault::kSensorStuck | io_fault::kSensorSaturated)) {
    flags |= shm::status::kBoardFault;
    if (!sensor_fault_seen) d.Record(EventKind::kSensorFault, faults);
    sensor_fault_seen = true;
  }
}

// the first cycle of a silence: its event, and the safe mode's reason should it last
void DriverLoop::RecordSilentRead(bool io_error, bool no_answer, bool nonfinite,
                                  const Finding& implausible) noexcept {
  if (io_error) {
    d.Record(EventKind::kIoError, d.in.silent_boards);
  } else if (no_answer) {
    d.Record(EventKind::kBoardSilent, d.in.silent_boards);
  } else if (nonfinite) {
    d.Record(EventKind::kBoardNonFinite, d.in.nonfinite_boards);
  }
  if (!no_answer && implausible.kind != CheckKind::kNone) {
    d.Record(EventKind::kImplausibleReading, 0, implausible.board, implausible.joint,
             implausible.value);
  }
  silent_reason =
      no_answer ? kSafeBoardSilent : nonfinite ? kSafeBoardNonFinite : kSafeBoardImplausible;
}

//---- emergency stop: servos off in this very cycle
void DriverLoop::EmergencyStop() noexcept {
  if (d.estopped || !((faults & io_fault::kEmergencyStop) || EmergencyStopRequested())) return;
  d.estopped = true;
  d.Record(EventKind::kEmergencyStop, (faults & io_fault::kEmergencyStop) ? 1 : 2);
  if (d.servo_on) d.Record(EventKind::kServoOff);
  d.servo_on = false;
  result_.exit_code = kExitEmergencyStop;
  outcome = "emergency_stop";
  done = true;
}

//---- board faults, end of data, servo-on
void DriverLoop::FaultsAndServoOn() noexcept {
  const bool running = d.state == DriverState::kActive;
  const bool inactive = d.state == DriverState::kInactive;
  if ((faults & io_fault::kEndOfData) && (running || inactive)) {
    d.Record(EventKind::kEndOfData);
    BeginStopping(kExitOk, "end_of_data");
  } else if (running && !reset_hold && (faults & io_fault::kBoardReset)) {
    BeginResetHold();
  } else if (running && reset_hold && silent_board < o.board_timeout_cycles) {
    ContinueResetHold();
  } else if (running && silent_board >= o.board_timeout_cycles) {
    EnterSafeMode(kExitBoardFault, "board_fault", silent_reason, Rearm::kNone);
  } else if (inactive && rearm != Rearm::kNone) {
    // after a recovered safe mode: servo-on again once it is safe (see driver.h)
    const bool clean = !silent && !(faults & io_fault::kBoardReset);
    clean_reads = clean ? clean_reads + 1 : 0;
    const bool ready = rearm == Rearm::kBoards ? clean_reads >= o.board_timeout_cycles
                                               : clean && d.producer->controller_pid() != 0;
    if (ready) ServoOn(true);
  } else if (inactive && !silent) {
    ServoOn(false);
  } else if (inactive && MonotonicNs() - t0 > servo_on_timeout) {
    d.Record(EventKind::kNoValidRead);
    result_.exit_code = kExitIo;
    outcome = "io_error";
    detail = "no valid read from the boards within the servo-on timeout (--servo-on-timeout)";
    done = true;
  }
}

// hold the posture through a board reset: re-arm the reset board's joints (servo off), keep
// every other joint at its reference, then ramp them back (ContinueResetHold)
void DriverLoop::BeginResetHold() noexcept {
  flags |= shm::status::kBoardFault;
  const bool boards = d.in.reports & io_report::kBoards;
  reset_mask = boards ? d.in.reset_boards : ~0u;
  int first_board = -1;
  for (int j = 0; j < d.njoint; ++j) {
    const int b = boards ? d.in.joint_board[j] : -1;
    d.rearm_joint[j] = !boards || (b >= 0 && (reset_mask & (1u << b)));
    if (!d.rearm_joint[j]) continue;
    if (first_board < 0) first_board = b;
    d.ramp_to[j] = d.guard.references()[j];
    d.joint_off[j] = true;
  }
  d.Record(EventKind::kBoardReset, reset_mask, first_board);
  d.Record(EventKind::kResetHold, reset_mask, first_board);
  reset_hold = true;
  reset_wait = 0;
  ramp_start = -1;
}

void DriverLoop::ContinueResetHold() noexcept {
  flags |= shm::status::kBoardFault;
  const bool boards = d.in.reports & io_report::kBoards;
  const bool still_reset =
      (faults & io_fault::kBoardReset) && (!boards || (d.in.reset_boards & reset_mask));
  if (ramp_start < 0 && !still_reset && !silent) {
    // re-armed: servo on where the joints are, then the ramp back to their references
    for (int j = 0; j < d.njoint; ++j) {
      if (!d.rearm_joint[j]) continue;
      d.ramp_from[j] = d.in.q[j];
      d.joint_off[j] = false;
    }
    ramp_start = MonotonicNs();
    ++result_.recoveries;
    d.Record(EventKind::kServoOn, result_.recoveries);
  } else if (ramp_start < 0 && ++reset_wait > rearm_cycles) {
    d.Record(EventKind::kBoardRearm, reset_mask);
    detail = "a reset board did not re-arm (its reset flag stayed on after the all-off "
             "command): its joints could not be held";
    EnterSafeMode(kExitBoardDisobeys, "board_disobeys", kSafeBoardReset, Rearm::kNone);
  }
  if (reset_hold && ramp_start >= 0) RampBackAfterReset();
}

// the re-armed joints from where they were measured back to their references
void DriverLoop::RampBackAfterReset() noexcept {
  const double s = std::min(1.0, static_cast<double>(MonotonicNs() - ramp_start) /
                                     static_cast<double>(ramp_ns));
  for (int j = 0; j < d.njoint; ++j) {
    if (!d.rearm_joint[j]) continue;
    shm::JointCommand c = d.ramp_to[j];
    double target = c.q_ref;
    if (c.mode != shm::JointMode::kPosition || c.kp <= 0) {  // not held by position
      c = shm::JointCommand{};
      c.mode = shm::JointMode::kPosition;
      c.kp = d.guard.default_kp(j);
      c.kd = d.guard.default_kd(j);
      target = d.ramp_from[j];
    }
    c.q_ref = d.ramp_from[j] + s * (target - d.ramp_from[j]);
    c.dq_ref = 0;
    d.guard.Set(j, c);
  }
  if (s >= 1.0) {
    EndResetHold();
    d.checks.Restart();
    d.Record(EventKind::kResetRamped, reset_mask);
  }
}

// servo-on holding the measured posture: the first one, or after a recovered safe mode
void DriverLoop::ServoOn(bool rearmed) noexcept {
  d.guard.HoldMeasured(d.in.q);
  if (rearmed) {
    rearm = Rearm::kNone;
    ++result_.recoveries;
  } else {
    d.checks.Restart();
    if (!d.have_imu_reference && d.nimu > 0) {
      std::memcpy(d.imu_reference, d.in.imu[0].quat_WI, sizeof(d.imu_reference));
      d.have_imu_reference = true;
    }
  }
  d.servo_on = true;
  d.state = DriverState::kActive;
  servoed_on = true;
  if (rearmed) {
    d.Record(EventKind::kServoOn, result_.recoveries);
  } else {
    d.Record(EventKind::kServoOn);
  }
}

//---- the cameras' frames (only while some program asks), then the sensors
void DriverLoop::Sensors() noexcept {
  if (d.ncamera > 0) {
    if (d.k % kImageRequestPollCycles == 0) d.images_wanted = d.producer->ImagesRequested();
    d.io->images(d.images_wanted, d.time, &d.images);
  }
  d.Publish(flags, live_);
}

//---- the controller's commands until the command deadline (from the cycle after a servo-on:
//---- the servo-on cycle's write holds the measured positions)
void DriverLoop::Commands() noexcept {
  const pid_t pid = d.producer->controller_pid();
  if (pid != 0 && pid != controller) {
    controller = pid;
    answered = false;
    silent_controller = 0;
    d.Record(EventKind::kControllerAttached, pid);
  }
  if (controller == 0) return;
  const double remaining =
      static_cast<double>(std::max<int64_t>(0, slot + window - MonotonicNs())) * 1e-9;
  switch (d.producer->WaitCommands(remaining, &d.cmd)) {
    case shm::WaitResult::kCommands:
      silent_controller = 0;
      if (reset_hold) break;  // the posture is held through a board reset: not the controller's
      Bump(live_.commands);
      d.last_command_cycle = d.cmd.answers_cycle;
      d.late_flag = 0;
      d.rejected_flag = 0;
      answered = true;
      d.NoteGuard();
      if (d.guard.Accept(d.cmd) > 0) d.rejected_flag = shm::status::kCommandRejected;
      live_.rejected.store(d.guard.rejected_total(), std::memory_order_relaxed);
      live_.clamped.store(d.guard.clamped_total(), std::memory_order_relaxed);
      break;
    case shm::WaitResult::kTimeout:
      if (!answered) break;  // a new controller is still setting up
      Bump(live_.late_commands);
      d.late_flag = shm::status::kCommandLate;
      if (++silent_controller >= o.watchdog_cycles) {
        d.Record(EventKind::kControllerSilent, silent_controller);
        EnterSafeMode(kExitControllerLost, "controller_lost", kSafeControllerSilent, on_loss);
        // alive but silent: let it go, so that a new controller can attach and this one
        // learns it was dropped should it run again (shm_bridge/controller_loss.h)
        d.producer->DropController(controller);
        controller = 0;
      }
      break;
    case shm::WaitResult::kControllerDied:
      d.Record(EventKind::kControllerDied, controller);
      if (answered) {
        EnterSafeMode(kExitControllerLost, "controller_lost", kSafeControllerDied, on_loss);
      }
      controller = 0;
      break;
    case shm::WaitResult::kNoController:
      d.Record(EventKind::kControllerDetached, controller);
      if (answered) {
        EnterSafeMode(kExitControllerLost, "controller_lost", kSafeControllerDetached, on_loss);
      }
      controller = 0;
      break;
  }
}

//---- stop requests and the duration
void DriverLoop::StopsAndDuration() noexcept {
  const bool active_or_inactive =
      d.state == DriverState::kActive || d.state == DriverState::kInactive;
  const int stops = StopRequests();
  if (stops > stops_seen) {
    if (stops_seen == 0) d.Record(EventKind::kStopRequested, stops);
    stops_seen = stops;
    if (active_or_inactive) {
      BeginStopping(kExitInterrupted, "interrupted");
    } else if (stops >= 2) {
      phase_end = 0;  // asked again: servos off in the next cycle
    }
  } else if (o.duration > 0 &&
             static_cast<double>(slot + period - t0) * 1e-9 >= o.duration - 0.5 * o.period &&
             active_or_inactive) {
    d.Record(EventKind::kDurationReached);
    BeginStopping(kExitOk, "completed");
  }
}

//---- next slot; skip the slots already over instead of running them in a burst
void DriverLoop::NextSlot() noexcept {
  ++d.k;
  slot += period;
  const int64_t behind = MonotonicNs() - slot;
  if (behind > period) {
    const int64_t skip = behind / period;
    slot += skip * period;
    Bump(live_.skipped, static_cast<uint64_t>(skip));
  }
}

//---- last block: what the run ended with
void DriverLoop::Finish() {
  d.time = static_cast<double>(slot - t0) * 1e-9;
  d.Publish(shm::status::kShuttingDown, live_, false);  // the last cycle's time again: not logged
  const bool failed = result_.exit_code != kExitOk && result_.exit_code != kExitInterrupted;
  d.producer->SetState(failed ? shm::ProducerState::kFailed : shm::ProducerState::kStopped);
  d.state = DriverState::kInactive;
  live_.state.store(static_cast<uint32_t>(d.state), std::memory_order_relaxed);
  result_.outcome = outcome;
  result_.detail = detail;
  result_.duration = d.time;
  result_.events = d.events;
  result_.events_dropped = d.events_dropped;
  result_.rejected_per_joint.assign(d.guard.rejected_per_joint(),
                                    d.guard.rejected_per_joint() + d.njoint);
}

}  // namespace ohrp::hw
