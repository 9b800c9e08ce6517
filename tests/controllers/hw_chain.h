// Test helpers for running a built controller program, unchanged, on the hardware path:
// hw_emulator (the boards, a MuJoCo HRP-1S behind them, real time) <- UDP -> hw_driver with
// libohrp_io_udp.so (2 ms servo cycle, real-time pacing) <- segment -> the controller. The
// emulator's CSV log (every 10th cycle) tells what the robot did.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ohrp::controllers::testing {

constexpr double kHalfSitHeight = 0.6839;  // base height of the halfsit keyframe [m]

// one row of the emulator's log
struct EmulatorRow {
  double t = 0, z = 0, tilt = 0;  // robot time [s], base height [m], tilt [deg]
  int on = 0;                     // servos on
  double x = 0, y = 0, yaw = 0;   // base position [m] and heading [deg] in the world
};

struct Chain {
  int driver = -1, controller = -1, emulator = -1;  // exit codes
  std::string controller_out, driver_out, emulator_out;
  std::vector<EmulatorRow> rows;
  nlohmann::json summary;  // the driver's --summary
};

// How long a silence the chain takes for a fault: the UDP plugin's board timeout (timeout_ms) and
// the driver's controller watchdog and board timeout (in 2 ms servo cycles).
struct Tolerance {
  int board_ms = 100;
  int cycles = 100;
};
// the fault tests time the latch against these (a silent board is flagged after 100 ms)
inline constexpr Tolerance kFaultTolerance = {100, 100};
// the runs that must end clean: a stall of the loaded VM (a process not scheduled for a few
// hundred milliseconds) or a controller slowed by the sanitizers (walk under ASan answered
// later than 200 ms at times) is not what they test, and must not read as a fault
inline constexpr Tolerance kStallTolerance = {1000, 500};

// Runs the emulator (flat scene, halfsit keyframe, `emulator_args` added), the driver
// (`duration` s of 2 ms servo cycles), then `controller` (a program of build/bin or a path, and
// its arguments; the segment is added); the emulator is stopped with SIGINT once the driver ended.
Chain RunChain(const std::string& tag, const std::vector<std::string>& controller,
               const std::vector<std::string>& emulator_args, double duration,
               Tolerance tolerance = kStallTolerance);

// The robot behind the boards: the emulator's and the driver's --model and the emulator's start
struct ChainRobot {
  std::string model;     // a scene or robot profile
  std::string keyframe;  // the emulator's initial state
  double period = 0.002; // the driver's servo cycle = the controller's period [s]
  std::vector<std::string> driver_args = {};  // added to hw_driver's (e.g. --log FILE)
};
// HRP-1S's flat scene, the robot RunChain runs on
std::string ChainScene();
// the same on another robot than HRP-1S's flat scene
Chain RunChainOn(const ChainRobot& robot, const std::string& tag,
                 const std::vector<std::string>& controller,
                 const std::vector<std::string>& emulator_args, double duration,
                 Tolerance tolerance = kStallTolerance);

// What to read when a run went wrong: the exit codes, the driver's summary (deadline misses,
// lateness, late commands, board faults) and the three programs' output.
std::string Diagnosis(const Chain& c);

// base height and tilt over [t0, t1] of robot time, all 29 servos on: {z_lo, z_hi, tilt_max}
std::array<double, 3> Span(const Chain& c, double t0, double t1);

// the programs the chain needs that are not built ("" when all are)
std::string MissingHwProgram(const std::string& controller);

}  // namespace ohrp::controllers::testing
