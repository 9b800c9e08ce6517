// hw_emulator's fault injection: what is wrong with the boards right now, the faults planned on
// the command line (at a robot time), and the run-time control file.
//
// Command-line events (T: robot time [s], i.e. the boards' clock, which starts with the first
// command; B: board id; S: a sensor, ft0..ft3 or imu0..imu1):
//   --silent B@T[+D]   board B stops answering (and listening) at T, for D seconds (default: for good)
//   --reset B@T        board B restarts at T: its servos go off, its numbering starts again
//   --stuck S@T        sensor S repeats the value it had at T
//   --saturate S@T     sensor S reads the end of its range from T on
//   --estop T[+D]      the emergency-stop input is pressed at T (for D seconds)
//   --value J=X@T[+D]  joint J's motor board reads X (e.g. nan, 1e300) as its position from T
//                      (for D seconds): a broken encoder or a corrupted board
//
// Control file (--control FILE): hw_emulator reads the lines appended to FILE while it runs
// (every kControlPollPeriod), one command per line; they act at once:
//   loss P | late P MS | silent B | talk B | reset B | stuck S | saturate S | sensor-ok S |
//   estop on | estop off | value J X | value off | clear
// ("clear" ends every fault but resets already done).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::hw::udp {

inline constexpr double kControlPollPeriod = 0.05;  // [s] wall time between control-file reads

// What is wrong right now (set by the plan and the control file, read by the emulator loop).
struct FaultState {
  double loss = 0;           // probability that a packet (either direction) is dropped [0..1]
  double late_rate = 0;      // fraction of state packets held back ... [0..1]
  double late_s = 0;         // ... by this long [s]
  uint32_t silent = 0;       // bit b: board b neither answers nor listens
  uint32_t stuck = 0;        // bit i: F/T sensor i stuck; bit 8+i: IMU i stuck
  uint32_t saturated = 0;    // same bits, saturated
  bool estop = false;
  int value_joint = -1;      // >= 0: this joint's board reads `value` as its position
  double value = 0;          // (any double: NaN and inf included)
  uint32_t reset_request = 0;  // bit b: restart board b now (the loop clears it)
};

enum class FaultKind {
  kSilent, kTalk, kReset, kStuck, kSaturate, kSensorOk, kEstop, kEstopOff, kValue, kValueOff
};

struct FaultEvent {
  double time = 0;   // robot time [s]
  FaultKind kind = FaultKind::kSilent;
  int target = 0;    // board id, or sensor bit (see FaultState::stuck), or joint id (kValue)
  bool done = false;
  double value = 0;  // kValue: what the joint reads
};

// Parses a sensor name (ft0..ft3, imu0..imu1) into its FaultState bit; -1 when malformed.
int SensorBit(const std::string& name, int nforce, int nimu);

// Parses "B@T[+D]" / "S@T" / "T[+D]" forms of the command-line options into events (a duration
// adds the ending event). Returns false with `*error` naming the option and the fix.
bool ParseEvent(const std::string& option, const std::string& value, int nboards, int nforce,
                int nimu, std::vector<FaultEvent>* events, std::string* error);

// Applies the events due at robot time `t` to `*state`.
void ApplyDue(double t, std::vector<FaultEvent>* events, FaultState* state);

// Applies one control-file line. Returns false with `*error` set when the line is malformed
// (the emulator reports it and goes on).
bool ApplyControlLine(const std::string& line, int nboards, int nforce, int nimu,
                      FaultState* state, std::string* error);

// Follows a control file: returns the complete lines appended since the last call.
class ControlFile {
 public:
  explicit ControlFile(std::string path) : path_(std::move(path)) {}
  std::vector<std::string> NewLines();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  long offset_ = 0;
  std::string partial_;
};

}  // namespace ohrp::hw::udp
