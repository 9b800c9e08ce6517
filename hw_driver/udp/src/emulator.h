// hw_emulator: the robot's boards on loopback UDP, with a MuJoCo model of the robot running in
// real time behind them (see PROTOCOL.md for the protocol, faults.h for fault injection).
//
// Each cycle (absolute-deadline sleeps on the monotonic clock):
//   1. drain the socket: the first hello binds the boards to its sender's address and session
//      id (PROTOCOL.md, "Sessions"); hellos and commands of anyone else are refused (counted,
//      and flagged `foreign` in the states); each motor board's commands are checked and
//      applied in order (servo on/off per joint, the servo's references, sim_host's Servo
//      refusing bad joints); a motor board without a valid command for --hold-ms holds its
//      joints where they are (position hold, the model's default gains) until the next one;
//   2. step the physics (period / timestep steps) with the motor boards' PD at every step, with
//      sim_host's physics step (sim_host/step.h): pushes, the servo, the contact under the
//      soles chosen as sim_host chooses it (--contact auto: the soft soles when the model has
//      soles; a profile's contact: and contact_file: honoured; --contact-stiffness/
//      --contact-damping: a robot whose feet differ from the simulation's, for identification,
//      docs/identify.md), mj_step;
//   3. answer one state packet per board (motor boards: q, dq, tau, servo state; the sensor
//      board: F/T and IMU), through the injected faults (loss, late, silent, stuck, saturated).
// The robot's time stands still until the first command packet arrives (the boards keep
// answering), so the robot does not fall before a driver is there. Servos start off.
#pragma once

#include <string>
#include <vector>

#include "plant_gap.h"

namespace ohrp::hw::udp {

struct EmulatorOptions {
  std::string model;               // MJCF scene
  std::string keyframe;            // initial state (empty: the model's)
  std::string host = "127.0.0.1";  // bound address
  int port = 7700;                 // bound port (0: any, see port_file)
  std::string port_file;           // the bound port is written there once bound
  std::string boards;              // motor boards' joint ranges (empty: DefaultLayout)
  double period = 0.001;           // board cycle [s], a multiple of the model's timestep
  double timestep = 0;             // physics step [s]; 0: the model's
  std::string contact = "auto";    // under the soles, chosen as sim_host chooses it
                                   // (sim_host/contact_choice.h): auto honours a profile's contact:
  std::string contact_file;        // soft soles' parameters; empty: a profile's contact_file
  double contact_stiffness = 0;    // soft soles' normal stiffness [N/m]; 0: the default
  double contact_damping = -1;     // soft soles' Hunt-Crossley damping [s/m]; < 0: the default
  std::vector<std::string> pushes; // T0,T1,FX,FY,FZ,TX,TY,TZ on the base (sim_host --push)
  double duration = 0;             // robot time to run [s]; 0: until SIGINT
  double wait_driver = 0;          // wall time to wait for the first command [s]; 0: forever
  double loss = 0;                 // packet loss probability, both directions
  double late_rate = 0, late_ms = 0;  // fraction of state packets held back by late_ms
  unsigned long seed = 1;          // of the loss and late draws
  double hold_ms = 50;             // a motor board with no valid command this long holds its
                                   // joints where they are, by itself [ms]
  std::vector<std::string> silent, reset, stuck, saturate, estop, values;  // planned faults
                                                                          // (faults.h)
  std::string control_file;        // run-time fault commands (faults.h)
  GapOptions gap;                  // the robot's differences from the model (plant_gap.h)
  std::string log_path;            // CSV: robot time, base height and tilt, faults
  int log_every = 10;              // cycles between log rows
  bool quiet = false;
};

inline constexpr int kEmuExitOk = 0;
inline constexpr int kEmuExitUsage = 2;
inline constexpr int kEmuExitMujoco = 3;
inline constexpr int kEmuExitDiverged = 4;
inline constexpr int kEmuExitNoDriver = 5;
inline constexpr int kEmuExitInterrupted = 130;

// Runs the emulator until the duration, SIGINT/SIGTERM or a failure; returns the exit code.
// Prints the end-of-run report on stderr, including one "hw_emulator: result key=value ..." line
// for scripts and tests.
int RunEmulator(const EmulatorOptions& options);

}  // namespace ohrp::hw::udp
