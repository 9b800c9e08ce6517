// One run of the driver's real-time loop (Driver::Run), cycle by cycle: the state that lives for
// one run and the named stages of a cycle. Internal to the driver library: the cycle and its
// state machine are driver_loop.cc, the holds, stops and safety checks driver_safety.cc.
#pragma once

#include <cstdint>

#include "driver_state.h"

namespace ohrp::hw {

// what the servos-off state after a recovered safe mode waits for before a new servo-on
enum class Rearm {
  kNone,        // nothing: the safe mode ends the run (or no safe mode happened)
  kController,  // a new controller attached (--on-controller-loss wait) and a valid read
  kBoards,      // board_timeout_cycles valid reads in a row without a reset (after a reset)
};

class DriverLoop {
 public:
  DriverLoop(Driver::Impl& d, DriverResult& result, LiveStats& live);

  // one cycle: read, decide, publish, exchange commands, write; false once the run has ended
  bool Cycle() noexcept;
  // the last block and the result's fields copied out of the loop (allocates: after the loop)
  void Finish();

 private:
  //---- the stages of a cycle (driver_loop.cc)
  void WaitForSlot() noexcept;
  void ReadBoards() noexcept;
  void RecordSilentRead(bool io_error, bool no_answer, bool nonfinite,
                        const Finding& implausible) noexcept;
  void EmergencyStop() noexcept;
  void FaultsAndServoOn() noexcept;
  void BeginResetHold() noexcept;
  void ContinueResetHold() noexcept;
  void RampBackAfterReset() noexcept;
  void ServoOn(bool rearmed) noexcept;
  void Sensors() noexcept;
  void Commands() noexcept;
  void StopsAndDuration() noexcept;
  void NextSlot() noexcept;

  //---- holds, stops and the boards' verification (driver_safety.cc)
  void EndResetHold() noexcept;
  void EnterSafeMode(int exit_code, const char* why, int64_t reason, Rearm then) noexcept;
  void BeginStopping(int exit_code, const char* why) noexcept;
  void CheckBoards() noexcept;
  void CheckHoldObeyed() noexcept;
  void CheckFall() noexcept;
  void EndOfHold() noexcept;

  Driver::Impl& d;
  const DriverOptions& o;
  DriverResult& result_;
  LiveStats& live_;

  // constants of the run
  const int64_t period;
  const int64_t window;  // the part of a period the controller's commands are waited for
  const int64_t servo_on_timeout;
  const Rearm on_loss;
  const int64_t t0;
  const int64_t ramp_ns;
  const int round_trip_cycles;
  const int rearm_cycles;

  // the loop's state
  int64_t slot;               // T_k
  int64_t phase_end = 0;      // end of the safe mode or of the servo-off damping [ns]
  int silent_board = 0;       // consecutive cycles with a silent board
  int silent_controller = 0;  // consecutive cycles without the controller's answer
  bool board_was_silent = false;
  int64_t silent_reason;      // why the boards gave no valid read (safe mode value)
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
  int stops_seen = 0;
  bool done = false;
  const char* outcome = "completed";  // copied into result_ after the loop (no allocation in it)
  const char* detail = "";

  // this cycle's
  uint32_t flags = 0;
  bool servoed_on = false;  // servo-on in this cycle: its write holds the measured positions
  bool silent = false;      // no valid read in this cycle
  uint32_t faults = 0;
};

}  // namespace ohrp::hw
