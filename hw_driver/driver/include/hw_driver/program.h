// The hw_driver program around the loop: reads the robot from its MJCF model (robot_model's
// parser), loads the IO plugin, opens the boards, creates the segment, runs the Driver, and
// writes the data log (--log, sim_host's format, by a thread off the loop), and
// reports: the lateness table and the events on stderr after the loop, a JSON summary
// (--summary), a stats file refreshed while it runs (--stats) and the table on SIGUSR1.
#pragma once

#include <string>
#include <vector>

#include "hw_driver/driver.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw {

struct ProgramOptions {
  std::string model;                  // MJCF file of the robot (e.g. mjcf/hrp1s/hrp1s.xml)
  std::string io_plugin;              // shared object exporting ohrp_create_robot_io
  std::vector<std::string> io_args;   // "key=value", handed to the plugin's open
  std::string segment = "hrp1s";
  std::string summary_path;           // JSON summary at the end; empty: none
  std::string stats_path;             // JSON stats rewritten every stats_interval; empty: none
  std::string log_path;               // CSV data log (datalog/recorder.h); empty: none
  bool log_dq = false;                // --log-dq: the log also records dq_<joint>
  uint64_t log_max = 0;               // [bytes] --log-max: the log's size bound; 0: none
  double stats_interval = 1.0;        // [s]
  bool quiet = false;                 // errors and warnings only
  DriverOptions driver;
};

// The segment's description of the robot in `model_path`: joints (names, limits, torque
// limits, default gains), force sensors, IMUs, cameras; kind hardware, physics_period 0,
// control period `period`. False with `*error` (MuJoCo's text and the file) on failure.
bool LoadRobotDescription(const std::string& model_path, const std::string& segment,
                          double period, shm::ProducerConfig* out, std::string* error);

// The safe mode's (and the stop's) damped hold with these options is one every joint's servo
// accepts (gains within (0, model::kMaxGain]); false with `*error` naming the option and the
// joint otherwise.
bool CheckHoldGains(const shm::ProducerConfig& robot, const DriverOptions& options,
                    std::string* error);

// Runs the whole program; returns its exit code (driver.h).
int RunProgram(const ProgramOptions& options);

// The lateness histogram as a small table (octaves, counts, percentiles) for humans.
std::string LatenessTable(const LatenessHistogram& h);

// The spin-tail's cost so far, for the lateness line: ", margin 41.0 us, spinning 2.3 % of the
// time" (empty with --wake sleep).
std::string WakeCost(const LiveStats& live, const DriverOptions& options);

// Writes the run's statistics as JSON to `path` (through a temporary file and a rename, so a
// reader never sees half a file). `result` may be null while the loop runs. False on I/O error.
bool WriteStats(const std::string& path, const ProgramOptions& options,
                const shm::ProducerConfig& robot, const LiveStats& live,
                const DriverResult* result);

}  // namespace ohrp::hw
