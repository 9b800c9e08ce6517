// The driver's real-time loop and its safety state machine (see driver.h). The loop's state is
// driver_state.h; the names of states and events names.cc; the stop requests requests.cc.
#include "hw_driver/driver.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "driver_state.h"
#include "requests.h"

namespace ohrp::hw {
namespace {

// what the servos-off state after a recovered safe mode waits for before a new servo-on
enum class Rearm {
  kNone,        // nothing: the safe mode ends the run (or no safe mode happened)
  kController,  // a new controller attached (--on-controller-loss wait) and a valid read
  kBoards,      // board_timeout_cycles valid reads in a row without a reset (after a reset)
};

// how long a board may take to show what it was last written (a round trip and a board cycle;
// up to 11 ms measured on a loaded machine), and to clear its reset flag after the re-arm
constexpr double kRoundTripTime = 0.02;  // [s]
constexpr double kRearmTime = 0.1;       // [s]

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

Driver::Driver(const DriverOptions& options, const shm::ProducerConfig& robot, RobotIo* io,
               shm::Producer* producer)
    : impl_(new Impl(options, robot, io, producer)) {}

Driver::~Driver() { delete impl_; }

void Driver::SetLog(model::Recorder* log) { impl_->log = log; }

const rt::RtReport& Driver::PrepareRealTime() {
  if (!rt_prepared_) {
    rt_ = rt::SetUpRealTime(impl_->opt.rt);
    rt_prepared_ = true;
  }
  return rt_;
}

//---------------- the loop ----------------

int Driver::Run() {
  Impl& d = *impl_;
  const DriverOptions& o = d.opt;
  result_ = DriverResult{};
  result_.rt = PrepareRealTime();

  const int64_t period = PeriodNs(o);
  const int64_t window =
      std::llround(static_cast<double>(period) * (1.0 - std::clamp(o.command_margin, 0.0, 0.9)));
  const int64_t servo_on_timeout = std::llround(o.servo_on_timeout * 1e9);
  const Rearm on_loss =
      o.on_controller_loss == shm::ControllerLoss::kWait ? Rearm::kController : Rearm::kNone;
  const int64_t t0 = MonotonicNs();
  int64_t slot = t0;          // T_k
  int64_t phase_end = 0;      // end of the safe mode or of the servo-off damping [ns]
  int silent_board = 0;       // consecutive cycles with a silent board
  int silent_controller = 0;  // consecutive cycles without the controller's answer
  bool board_was_silent = false;
  int64_t silent_reason = kSafeBoardSilent;  // why the boards gave no valid read (safe mode value)
  bool sensor_fault_seen = false;
  Rearm after_safe_mode = Rearm::kNone;  // what the current safe mode recovers to
  Rearm rearm = Rearm::kNone;            // what the servos-off state waits for before servo-on
  int clean_reads = 0;                   // consecutive valid reads without a reset, re-arming
  pid_t controller = 0;
  bool answered = false;      // the current controller has answered at least once
  bool reset_hold = false;    // holding the posture through a board reset (re-arm, ramp)
  uint32_t reset_mask = 0;    // the reset boards (all bits: the plugin does not say)
  int reset_wait = 0;         // cycles waited for the re-arm
  int64_t ramp_start = -1;    // the ramp back after the re-arm began [ns]; -1: re-arming
  int refused_in_hold = 0;    // consecutive cycles a board refused the safe mode's hold
  int hold_cycles = 0;        // cycles since the safe mode or stop began
  bool hold_refused = false;  // kSafeModeRefused recorded
  bool fell = false;          // kFall recorded
  const int64_t ramp_ns = std::max<int64_t>(1, std::llround(o.reset_ramp_time * 1e9));
  const int round_trip_cycles =
      std::max(2, static_cast<int>(std::ceil(kRoundTripTime / std::max(o.period, 1e-6))));
  const int rearm_cycles = std::max(
      o.board_timeout_cycles, static_cast<int>(std::ceil(kRearmTime / std::max(o.period, 1e-6))));
  int stops_seen = 0;
  bool done = false;
  const char* outcome = "completed";  // copied into result_ after the loop (no allocation in it)
  const char* detail = "";

  auto end_reset_hold = [&] {
    reset_hold = false;
    for (int j = 0; j < d.njoint; ++j) d.joint_off[j] = false;
  };
  auto enter_safe_mode = [&](int exit_code, const char* why, int64_t reason, Rearm then) {
    end_reset_hold();
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
  };
  auto begin_stopping = [&](int exit_code, const char* why) {
    result_.exit_code = exit_code;
    outcome = why;
    if (!d.servo_on) {
      done = true;
      return;
    }
    end_reset_hold();
    hold_cycles = 0;
    refused_in_hold = 0;
    d.state = DriverState::kStopping;
    d.guard.Damp(d.last_valid_q, o.safe_kp_scale, o.safe_kd_scale);
    phase_end = MonotonicNs() + std::llround(o.servo_off_time * 1e9);
  };

  // The boards' verification of one cycle with a valid read (see board_checks.h): a board that
  // disobeys ends the active state in a safe mode; the IMU's tilt past fall_tilt is a fall; a
  // board refusing the hold of a safe mode or stop is a failure of its own.
  auto check_boards = [&](uint32_t* flags, bool servoed_on) {
    if (d.state == DriverState::kActive && d.servo_on && !servoed_on) {
      bool skip[shm::kMaxJoints];
      for (int j = 0; j < d.njoint; ++j) skip[j] = reset_hold && d.rearm_joint[j];
      const Finding f = d.checks.Obeyed(d.in, d.commanded_on, d.guard.references(), skip);
      if (f.kind != CheckKind::kNone) {
        *flags |= shm::status::kBoardFault;
        d.Record(EventOf(f.kind), f.joint < 0 ? static_cast<int64_t>(f.value) : 0, f.board,
                 f.joint, f.value);
        detail = "a board did not do what it was commanded (see the events)";
        enter_safe_mode(kExitBoardDisobeys, "board_disobeys", kSafeBoardDisobeys, Rearm::kNone);
      }
    }
    if (d.state == DriverState::kSafeMode || d.state == DriverState::kStopping) {
      ++hold_cycles;
      const uint32_t refused = (d.in.reports & io_report::kBoards)
                                   ? d.in.refused_boards & ~d.in.reset_boards : 0u;
      refused_in_hold = refused && hold_cycles > round_trip_cycles ? refused_in_hold + 1 : 0;
      if (refused_in_hold >= round_trip_cycles && !hold_refused) {
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
    }
    if (o.fall_tilt > 0 && d.have_imu_reference && !fell &&
        (d.state == DriverState::kActive || d.state == DriverState::kSafeMode ||
         d.state == DriverState::kStopping)) {
      const double tilt = TiltBetween(d.imu_reference, d.in.imu[0].quat_WI);
      if (tilt > o.fall_tilt) {
        fell = true;
        d.Record(EventKind::kFall, 0, -1, -1, tilt);
        detail = "the robot fell: its IMU tilted past --fall-tilt";
        if (d.state == DriverState::kActive) {
          enter_safe_mode(kExitFall, "fall", kSafeFall, Rearm::kNone);
        } else {
          result_.exit_code = kExitFall;
          outcome = "fall";
        }
      }
    }
  };

  for (;;) {
    d.time = static_cast<double>(slot - t0) * 1e-9;
    if (d.k > 0) {
      live_.lateness.Add(d.waker.WaitUntil(slot) - slot);
      live_.spin_ns.store(d.waker.spin_ns(), std::memory_order_relaxed);
      live_.wake_margin_ns.store(d.waker.margin_ns(), std::memory_order_relaxed);
    }
    uint32_t flags = 0;
    bool servoed_on = false;  // servo-on in this cycle: its write holds the measured positions

    //---- read the boards
    const IoResult r = d.io->read(&d.in);
    const uint32_t faults = r == IoResult::kError ? 0u : d.in.faults;
    live_.packets_lost.store(d.in.packets_lost, std::memory_order_relaxed);
    // a NaN or inf from a board is no valid read either, but named as what it is; so is a
    // reading no joint can give (board_checks.h: outside the range's margin, too fast)
    const bool nonfinite = (faults & io_fault::kNonFinite) || !AllFinite(d.in.q, d.njoint);
    const bool no_answer = r == IoResult::kError || (faults & io_fault::kBoardSilent);
    const Finding implausible = no_answer ? Finding{} : d.checks.Plausible(d.in);
    const bool bad_values = nonfinite || implausible.kind != CheckKind::kNone;
    const bool silent = no_answer || bad_values;
    if (silent) {
      Bump(live_.silent_reads);
      ++silent_board;
      flags |= shm::status::kBoardFault;
      if (!board_was_silent) {
        if (r == IoResult::kError) {
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
        silent_reason = no_answer ? kSafeBoardSilent
                                  : nonfinite ? kSafeBoardNonFinite : kSafeBoardImplausible;
      }
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

    //---- emergency stop: servos off in this very cycle
    if (!d.estopped && ((faults & io_fault::kEmergencyStop) ||
                        EmergencyStopRequested())) {
      d.estopped = true;
      d.Record(EventKind::kEmergencyStop, (faults & io_fault::kEmergencyStop) ? 1 : 2);
      if (d.servo_on) d.Record(EventKind::kServoOff);
      d.servo_on = false;
      result_.exit_code = kExitEmergencyStop;
      outcome = "emergency_stop";
      done = true;
    }

    //---- board faults, end of data, servo-on
    if (!done) {
      const bool running = d.state == DriverState::kActive;
      if ((faults & io_fault::kEndOfData) &&
          (running || d.state == DriverState::kInactive)) {
        d.Record(EventKind::kEndOfData);
        begin_stopping(kExitOk, "end_of_data");
      } else if (running && !reset_hold && (faults & io_fault::kBoardReset)) {
        // hold the posture through the reset: re-arm the reset board's joints (servo off),
        // keep every other joint at its reference, then ramp them back (below)
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
      } else if (running && reset_hold && silent_board < o.board_timeout_cycles) {
        flags |= shm::status::kBoardFault;
        const bool boards = d.in.reports & io_report::kBoards;
        const bool still_reset = (faults & io_fault::kBoardReset) &&
                                 (!boards || (d.in.reset_boards & reset_mask));
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
          enter_safe_mode(kExitBoardDisobeys, "board_disobeys", kSafeBoardReset, Rearm::kNone);
        }
        if (reset_hold && ramp_start >= 0) {
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
            end_reset_hold();
            d.checks.Restart();
            d.Record(EventKind::kResetRamped, reset_mask);
          }
        }
      } else if (running && silent_board >= o.board_timeout_cycles) {
        enter_safe_mode(kExitBoardFault, "board_fault", silent_reason, Rearm::kNone);
      } else if (d.state == DriverState::kInactive && rearm != Rearm::kNone) {
        // after a recovered safe mode: servo-on again once it is safe (see driver.h)
        const bool clean = !silent && !(faults & io_fault::kBoardReset);
        clean_reads = clean ? clean_reads + 1 : 0;
        const bool ready = rearm == Rearm::kBoards ? clean_reads >= o.board_timeout_cycles
                                                   : clean && d.producer->controller_pid() != 0;
        if (ready) {
          d.guard.HoldMeasured(d.in.q);
          d.servo_on = true;
          d.state = DriverState::kActive;
          servoed_on = true;
          rearm = Rearm::kNone;
          ++result_.recoveries;
          d.Record(EventKind::kServoOn, result_.recoveries);
        }
      } else if (d.state == DriverState::kInactive && !silent) {
        d.guard.HoldMeasured(d.in.q);
        d.checks.Restart();
        if (!d.have_imu_reference && d.nimu > 0) {
          std::memcpy(d.imu_reference, d.in.imu[0].quat_WI, sizeof(d.imu_reference));
          d.have_imu_reference = true;
        }
        d.servo_on = true;
        d.state = DriverState::kActive;
        servoed_on = true;
        d.Record(EventKind::kServoOn);
      } else if (d.state == DriverState::kInactive && MonotonicNs() - t0 > servo_on_timeout) {
        d.Record(EventKind::kNoValidRead);
        result_.exit_code = kExitIo;
        outcome = "io_error";
        detail = "no valid read from the boards within the servo-on timeout (--servo-on-timeout)";
        done = true;
      }
    }

    //---- the boards' verification (board_checks.h), the fall, the holds refused
    if (!done && !silent) check_boards(&flags, servoed_on);

    //---- the cameras' frames (only while some program asks), then the sensors; then the
    //---- controller's commands until the command deadline (from the cycle after a servo-on:
    //---- the servo-on cycle's write holds the measured positions)
    if (d.ncamera > 0) {
      if (d.k % kImageRequestPollCycles == 0) d.images_wanted = d.producer->ImagesRequested();
      d.io->images(d.images_wanted, d.time, &d.images);
    }
    d.Publish(flags, live_);
    if (!done && d.state == DriverState::kActive && !servoed_on) {
      const pid_t pid = d.producer->controller_pid();
      if (pid != 0 && pid != controller) {
        controller = pid;
        answered = false;
        silent_controller = 0;
        d.Record(EventKind::kControllerAttached, pid);
      }
      if (controller != 0) {
        const double remaining =
            static_cast<double>(std::max<int64_t>(0, slot + window - MonotonicNs())) * 1e-9;
        switch (d.producer->WaitCommands(remaining, &d.cmd)) {
          case shm::WaitResult::kCommands:
            if (reset_hold) {  // the posture is held through a board reset: not the controller's
              silent_controller = 0;
              break;
            }
            Bump(live_.commands);
            d.last_command_cycle = d.cmd.answers_cycle;
            d.late_flag = 0;
            d.rejected_flag = 0;
            silent_controller = 0;
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
              enter_safe_mode(kExitControllerLost, "controller_lost", kSafeControllerSilent,
                              on_loss);
              // alive but silent: let it go, so that a new controller can attach and this one
              // learns it was dropped should it run again (shm_bridge/controller_loss.h)
              d.producer->DropController(controller);
              controller = 0;
            }
            break;
          case shm::WaitResult::kControllerDied:
            d.Record(EventKind::kControllerDied, controller);
            if (answered) {
              enter_safe_mode(kExitControllerLost, "controller_lost", kSafeControllerDied, on_loss);
            }
            controller = 0;
            break;
          case shm::WaitResult::kNoController:
            d.Record(EventKind::kControllerDetached, controller);
            if (answered) {
              enter_safe_mode(kExitControllerLost, "controller_lost", kSafeControllerDetached,
                              on_loss);
            }
            controller = 0;
            break;
        }
      }
    }

    //---- the end of a damped hold: servos off; the run ends, or waits to servo on again
    if (!done && (d.state == DriverState::kSafeMode || d.state == DriverState::kStopping) &&
        MonotonicNs() >= phase_end) {
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
        d.Record(rearm == Rearm::kBoards ? EventKind::kBoardRearm
                                         : EventKind::kWaitingForController);
      } else {
        done = true;
      }
    }

    //---- write the boards
    d.Write();
    if (MonotonicNs() > slot + period) Bump(live_.deadline_misses);
    live_.cycles.store(d.k + 1, std::memory_order_relaxed);
    live_.state.store(static_cast<uint32_t>(d.state), std::memory_order_relaxed);
    if (done) break;

    //---- stop requests and the duration
    const int stops = StopRequests();
    if (stops > stops_seen) {
      if (stops_seen == 0) d.Record(EventKind::kStopRequested, stops);
      stops_seen = stops;
      if (d.state == DriverState::kActive || d.state == DriverState::kInactive) {
        begin_stopping(kExitInterrupted, "interrupted");
      } else if (stops >= 2) {
        phase_end = 0;  // asked again: servos off in the next cycle
      }
    } else if (o.duration > 0 && static_cast<double>(slot + period - t0) * 1e-9 >=
                                     o.duration - 0.5 * o.period &&
               (d.state == DriverState::kActive || d.state == DriverState::kInactive)) {
      d.Record(EventKind::kDurationReached);
      begin_stopping(kExitOk, "completed");
    }
    if (done) break;

    //---- next slot; skip the slots already over instead of running them in a burst
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
  return result_.exit_code;
}

}  // namespace ohrp::hw
