// hw_driver: the real-time producer that runs beside the robot. It creates the robot's segment
// (producer kind hardware) and, every servo cycle, reads the boards through a RobotIo plugin,
// publishes the sensor block, waits for the controller's commands until the cycle's command
// deadline, checks them (guard.h) and writes the boards. The controller cannot tell it from
// sim_host: same segment, same handshake (shm_bridge/layout.h).
//
// ---------------------------------------------------------------------------------------------
// Timing. The servo cycle is the segment's control cycle (`period`, 1 ms by default): there is
// no separate physics step on the robot (header physics_period = 0). Cycle k starts at the
// absolute time T_k = T_0 + k period (CLOCK_MONOTONIC); the loop waits for it as
// DriverOptions::wake says (wake.h: by default clock_nanosleep TIMER_ABSTIME to T_k minus a
// margin learned from the sleeps' lateness, then a spin on the clock to T_k); its wake-up
// lateness (now - T_k) goes into a histogram. Within the cycle:
//   read boards -> publish sensors (cycle k, time k period) -> wait for the commands answering
//   k until T_k + (1 - command_margin) period -> check -> write boards -> sleep until T_{k+1}.
// Commands that miss the deadline are counted as late (status kCommandLate) and the joints keep
// their last references. A cycle whose write ends after T_{k+1} is a deadline miss; when the
// loop falls more than one period behind, the missed slots are skipped (counted), not run in a
// burst. The loop never allocates, throws or logs: events go into a preallocated log printed
// after the loop. It busy-waits only in the spin-tail of the wake-up, bounded by the margin.
//
// Lifecycle (the controllers' state machine, controllers/controller.h, seen from the driver):
//
//              configure                 activate (first valid read)
//   kUnconfigured -----> kInactive ---------------------------------> kActive <- commands
//                        servos off       hold measured q, default gains,   |    accepted
//                         ^    ^          servos on                         |
//                         |    |               watchdog / board fault       v
//                         |    |   servo-off  <------------------------- kSafeMode: damped hold
//                         |    +--- (end of run) <- kStopping: damped hold  of the last valid
//                         |    |       ^              (stop, duration, end   references for
//                         |    |       |               of data)              safe_time
//                         |    +-- emergency stop: servos off at once, from any state
//                         +------ servo-off, then servo-on again when safe (recovery): after a
//                                 board reset, and after a lost controller with
//                                 --on-controller-loss wait
//   close: boards closed, segment removed -> kClosed.
//
//   configure   Create: the boards are opened (IoConfig) and the segment exists; sensors are
//               published from the first cycle on (servos off until activate).
//   activate    on the first valid read (no kBoardSilent, read not kError): hold the measured
//               positions with the default gains, servos on. No valid read within
//               servo_on_timeout ends the run (kExitIo).
//   run         controller's commands checked and clamped, written to the boards.
//   safe mode   entered when the controller stays silent for watchdog_cycles cycles after its
//               first answer, dies (pid check in every command wait), or detaches; when a
//               board is silent or sends a NaN or inf (event board_non_finite) or an
//               implausible value (event implausible_reading with board, joint and value;
//               board_checks.h) for board_timeout_cycles cycles; when a board disobeys
//               (board_checks.h: servo state, acknowledgements, tracking, refused or foreign
//               commands; exit kExitBoardDisobeys); when the IMU tilts past fall_tilt from its
//               pose at servo-on (event fall, exit kExitFall). Commands are ignored; after
//               safe_time the servos go off and the run ends, except after a lost controller
//               with on_controller_loss kWait (recovery). A board refusing the hold is event
//               safe_mode_refused and exit kExitBoardDisobeys.
//   board reset held through, no safe mode: in the cycle the reset is read (events
//               board_reset, reset_hold) the reset board's joints are written servo-off (the
//               re-arm of udp/PROTOCOL.md) while the others keep their references; at the
//               first read without the reset flag they servo on where measured (event servo_on
//               with the recovery's number) and ramp back to their references in
//               reset_ramp_time (event reset_ramped); the controller's commands are ignored
//               meanwhile. No re-arm within board_timeout_cycles or 100 ms, whichever is
//               longer: safe mode, kExitBoardDisobeys.
//   recovery    a lost controller with on_controller_loss kWait: after the servo-off the
//               driver waits (event waiting_for_controller) for a new controller to attach,
//               then servo-on as at the start, with a valid read. A silent controller is
//               dropped from the segment when it is declared lost (Producer::DropController):
//               resumed, its next read returns kDropped and it exits non-zero. A recovery sets
//               the run's outcome back to completed: how the run ends decides its exit code;
//               the summary keeps safe_mode, the events and the number of recoveries.
//   stopping    SIGINT/SIGTERM, the duration reached or the replay's end of data: a damped
//               hold for servo_off_time, then servos off, run ends.
//   e-stop      IoState fault kEmergencyStop or SIGUSR2 (RequestEmergencyStop): the write of
//               the same cycle turns every servo off; the run ends.
// Status bits published (shm::status): kRunning always; kNoController while no controller is
// attached; kCommandLate when the last commands missed their deadline; kCommandRejected when a
// joint was rejected this cycle; kHolding in safe mode and while stopping; kServoOff while the
// servos are off; kBoardFault when a board is silent, reset, sends a NaN or inf, or reports a
// stuck or saturated sensor this cycle; kEmergencyStop after an emergency stop; kShuttingDown on the last block.
// ---------------------------------------------------------------------------------------------
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "hw_driver/lateness.h"
#include "hw_driver/robot_io.h"
#include "shm_bridge/realtime.h"
#include "hw_driver/wake.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/controller_loss.h"

namespace ohrp::datalog {
class Recorder;
}

namespace ohrp::hw {

// exit codes of hw_driver (the same numbers as sim_host's where the meaning is the same)
inline constexpr int kExitOk = 0;              // duration reached, or the replay ended
inline constexpr int kExitUsage = 2;           // bad option, model, plugin file or segment
inline constexpr int kExitIo = 3;              // the boards failed: open, or no valid read
inline constexpr int kExitControllerLost = 5;  // controller silent, dead or detached: safe mode
inline constexpr int kExitBoardFault = 6;      // a board silent or sending NaN: safe mode
inline constexpr int kExitEmergencyStop = 7;   // emergency stop: servos off at once
inline constexpr int kExitBoardDisobeys = 8;   // a board does not do what it was commanded (servo
                                               // state, acknowledgement, tracking, refused or
                                               // foreign commands, a reset not re-armed): safe mode
inline constexpr int kExitFall = 10;           // the IMU says the robot fell: safe mode
inline constexpr int kExitInterrupted = 130;   // SIGINT / SIGTERM: servo-off, clean shutdown

enum class DriverState { kUnconfigured, kInactive, kActive, kSafeMode, kStopping, kClosed };
const char* DriverStateName(DriverState s);

struct DriverOptions {
  double period = 0.001;           // servo cycle = control cycle [s]
  double command_margin = 0.1;     // part of the period kept after the command wait, for the
                                   // checks and the boards' write (0..0.9)
  int watchdog_cycles = 20;        // controller silent this many cycles (after its first
                                   // answer) -> safe mode
  int board_timeout_cycles = 10;   // a board silent this many cycles -> safe mode
  double safe_time = 1.0;          // [s] damped hold in safe mode before servo-off
  double servo_off_time = 0.2;     // [s] damped hold before servo-off at a normal stop
  double safe_kp_scale = 0.2;      // damped hold: kp = default_kp * this
  double safe_kd_scale = 2.0;      //              kd = default_kd * this
  double servo_on_timeout = 1.0;   // [s] for the boards' first valid read
  double duration = 0;             // [s] of driver time, then stop; 0: until stopped
  // a lost controller: kEnd ends the run after the safe mode; kWait turns the servos off and
  // waits for a new controller (kContinue is not offered: the robot is not left without one)
  shm::ControllerLoss on_controller_loss = shm::ControllerLoss::kEnd;
  rt::RtSettings rt;
  WakeOptions wake;                // how each cycle waits for its start (wake.h)
  int log_every = 1;               // cycles between rows of the data log (Driver::SetLog)
  // the data log's time: the boards' timestamp of the data (IoState::time_ns, the robot's time)
  // instead of the driver's cycle; a cycle whose boards' time did not advance past the last
  // row's is not logged (its data repeat a row's: a read that found no new state)
  bool log_board_time = false;
  double tracking_time = 0.25;     // [s] a tracking error may last this long (board_checks.h)
  double reset_ramp_time = 0.2;    // [s] after a board reset: its joints ramp back from the
                                   // measured posture to their references
  double fall_tilt = 0.7854;       // [rad] IMU tilt from its pose at servo-on: a fall (0: off)
};

// One thing that happened in the loop, recorded without allocation and printed after it.
enum class EventKind {
  kServoOn, kControllerAttached, kControllerSilent, kControllerDied, kControllerDetached,
  kBoardSilent, kBoardBack, kBoardReset, kSensorFault, kSafeMode, kServoOff, kEmergencyStop,
  kEndOfData, kStopRequested, kDurationReached, kIoError, kNoValidRead,
  kBoardNonFinite,  // a board sent a NaN or inf: no valid read (value: IoState::nonfinite_boards)
  kWaitingForController,  // servos off after a lost controller; waiting for a new one
  kBoardRearm,            // servos off after a board reset (its re-arm); waiting for clean reads
  // the boards' verification (board_checks.h): board, joint and reading in the event
  kImplausibleReading,    // a joint read outside what it can (reading: the value)
  kServoMismatch,         // a servo not as commanded (reading: the state reported)
  kCommandsUnacknowledged,  // a board acknowledges no new command (value: board mask)
  kTrackingError,         // a joint too far from its reference too long (reading: ref - q)
  kCommandRefused,        // a board refused the driver's command (value: board mask)
  kForeignCommand,        // a board refused commands of another sender (value: board mask)
  kSafeModeRefused,       // a board refused the safe mode's (or stop's) hold (value: board mask)
  kResetHold,             // a board reset: its joints re-armed, the others hold (value: mask)
  kResetRamped,           // the reset board's joints are back at their references
  kFall,                  // the IMU's tilt passed --fall-tilt (reading: the tilt [rad])
  // the controller's self-collision guard (the command block's guard record, shm::GuardRecord)
  kGuardHoldBegin,        // it began to hold the motion (value: its hold episodes begun so
                          // far; reading: the held pair's predicted distance [m])
  kGuardHoldEnd,          // it let the motion go again (value, reading: as at the begin)
};
const char* EventName(EventKind k);

// Event::value of kSafeMode: why the safe mode began
inline constexpr int64_t kSafeBoardSilent = 1;
inline constexpr int64_t kSafeBoardReset = 2;
inline constexpr int64_t kSafeControllerSilent = 3;
inline constexpr int64_t kSafeControllerDied = 4;
inline constexpr int64_t kSafeControllerDetached = 5;
inline constexpr int64_t kSafeBoardNonFinite = 6;  // a board's data held a NaN or inf
inline constexpr int64_t kSafeBoardImplausible = 7;  // a board's data were implausible
inline constexpr int64_t kSafeBoardDisobeys = 8;     // a board disobeyed (board_checks.h)
inline constexpr int64_t kSafeFall = 9;              // the robot fell (IMU tilt)

struct Event {
  uint64_t cycle;
  double time;      // driver time [s]
  EventKind kind;
  int64_t value;    // kind-specific: a pid, a board mask, a count
  int board = -1;   // the board concerned, when known
  int joint = -1;   // the joint concerned (joint id), when one is
  double reading = 0;  // the value read, for the boards' verification events
};

// Counters readable while the loop runs (relaxed atomics written by the loop only).
struct LiveStats {
  std::atomic<uint64_t> cycles{0};           // cycles run
  std::atomic<uint64_t> deadline_misses{0};  // cycles whose write ended after the next start
  std::atomic<uint64_t> skipped{0};          // period slots skipped to catch up
  std::atomic<uint64_t> commands{0};         // command blocks accepted
  std::atomic<uint64_t> late_commands{0};
  std::atomic<uint64_t> rejected{0};         // joint commands rejected
  std::atomic<uint64_t> clamped{0};          // position references clamped into range
  std::atomic<uint64_t> silent_reads{0};     // reads with a silent board or a read error
  std::atomic<uint64_t> packets_lost{0};     // as the plugin counts them
  std::atomic<uint32_t> state{0};            // DriverState
  LatenessHistogram lateness;                // wake-up lateness [ns]
  std::atomic<int64_t> spin_ns{0};           // time spent spinning to the cycle starts [ns]
  std::atomic<int64_t> wake_margin_ns{0};    // the spin-tail's current learned margin [ns]
};

// What the run came to, for the report and the summary.
struct DriverResult {
  int exit_code = kExitOk;
  std::string outcome = "completed";  // completed | end_of_data | interrupted | controller_lost
                                      // | board_fault | board_disobeys | fall | emergency_stop
                                      // | io_error
  std::string detail;
  double duration = 0;                // driver time run [s]
  uint64_t safe_mode_cycle = 0;       // cycle at which safe mode began (0 and !safe_mode: never)
  bool safe_mode = false;
  int recoveries = 0;                 // servo-ons after a recovered safe mode
  std::vector<Event> events;
  uint64_t events_dropped = 0;
  std::vector<uint32_t> rejected_per_joint;
  rt::RtReport rt;
};

// Asks a running driver to stop (servo-off sequence) or to stop at once (emergency stop).
// Async-signal-safe; InstallSignalHandlers routes SIGINT/SIGTERM and SIGUSR2 to them.
void RequestStop() noexcept;
void RequestEmergencyStop() noexcept;
void ClearRequests() noexcept;
void InstallSignalHandlers();

class Driver {
 public:
  // `robot` describes the joints (limits, default gains) exactly as the segment's header;
  // `io` is open; `producer` owns the segment. None is owned; all outlive the driver. Throws
  // std::invalid_argument when options.wake is out of range (wake.h's MarginLearner says how).
  Driver(const DriverOptions& options, const shm::ProducerConfig& robot, RobotIo* io,
         shm::Producer* producer);
  ~Driver();
  Driver(const Driver&) = delete;
  Driver& operator=(const Driver&) = delete;

  // Applies options.rt to the calling thread (SCHED_FIFO, mlockall, stack) once; Run calls it
  // when the caller did not. Call it first to print its warnings before the loop starts.
  const rt::RtReport& PrepareRealTime();

  // The data log (datalog/recorder.h, sim_host's format without the ground-truth base
  // columns): each published sensor block (every options.log_every cycles; not the closing
  // kShuttingDown block, which repeats the last cycle's time) is copied into the log's ring; its thread writes the file. Not owned; outlives
  // Run. Call before Run.
  void SetLog(datalog::Recorder* log);

  // Runs the loop on the calling thread until the run ends; returns the exit code (also in
  // result()). Run once per Driver.
  int Run();

  const LiveStats& live() const { return live_; }
  const DriverResult& result() const { return result_; }

 private:
  struct Impl;
  friend class DriverLoop;  // the loop of one run (driver_loop.h)
  Impl* impl_;
  LiveStats live_;
  DriverResult result_;
  rt::RtReport rt_;
  bool rt_prepared_ = false;
};

}  // namespace ohrp::hw
