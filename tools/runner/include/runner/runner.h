// ohrp_run: one headless scripted run. Starts sim_host and the scenario's controllers as
// separate processes side by side on a fresh segment, runs for the scenario's duration,
// evaluates its checks and writes into the output folder:
//   summary.json      verdict, each check with its value, simulated and wall time, real-time
//                     factor, steps, each process's exit status
//   log.csv           sim_host's data log (see sim_host/recorder.h)
//   sim_summary.json  sim_host's own end-of-run summary
//   plot.png          base height and position, foot forces, a few joints against time, and
//                     the walk's panels when a controller wrote walk.csv there
//   *.stderr          what each process printed
// and what the controllers write there themselves, e.g. walk.csv (`--log "{out}/walk.csv"`)
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "runner/checks.h"
#include "runner/scenario.h"

namespace ohrp::runner {

struct RunOptions {
  std::string out_dir;      // empty: runs/<name>-<date>-<time> under the current directory
  std::string source_dir;   // data folder (cli::DataDir()): a scenario's relative paths start here
  std::string bin_dir;      // where sim_host and the controllers are
  std::string segment;      // empty: run_<name>_<pid>
  bool plot = true;
  bool echo = true;         // echo the processes' output, prefixed, while they run
  bool report = true;       // print the start line and the table of checks (off for tools
                            // that run many trials, e.g. tools/push)
};

// exit codes of ohrp_run
inline constexpr int kRunPassed = 0;
inline constexpr int kRunFailed = 1;       // a check failed or a process ended badly
inline constexpr int kRunUsage = 2;        // bad scenario or options
inline constexpr int kRunInterrupted = 130;

int RunScenario(const Scenario& scenario, const RunOptions& options);

// The names scenario `s` gives checked against the model of its scene (the file `scene`, resolved):
// plot_joints and plot_torques are joints of the robot (driven or passive), fall_allow_contact bodies, the checks'
// `sensors` and `sensor` force sensors, `geom` a geom and `camera` a camera of the scene. False
// with `*error` naming the scenario file, the line, the key, the name and the ones there are.
// RunScenario calls it before anything starts (exit kRunUsage).
bool CheckScenarioNames(const Scenario& s, const std::string& scene, std::string* error);

// The implicit check `sim_host_completed` from sim_host's exit code and summary: passes on exit 0
// without a fall, or, when the scenario expects a fall (`expect_fall: true`), on sim_host's fall
// (exit 6, the summary's "fall"); the detail names the fall's time and cause ("fell at t=1.234 s
// (cycle 246): body X touched floor ..."). `aborted`: why the run was stopped, if it was.
// `controller_fall`: a controller's own report of a fall (ControllerFall), "" when none: a fall
// too (the controller saw it first, left, and sim_host then lost its controller).
CheckResult SimHostCompleted(const Scenario& s, int exit_code, const nlohmann::json& sim_summary,
                             const std::string& aborted, const std::string& controller_fall = "");

// The controllers' exit code for "the robot fell" (controllers/runner.h, kExitFell).
inline constexpr int kControllerExitFell = 8;
// ... and for "the controller could not do what it was asked" (kExitFailed; e.g. a motion its
// self-collision guard stopped): the scenario's <label>_exited_cleanly check then gives the
// controller's own "FAILED: ..." line as its detail.
inline constexpr int kControllerExitFailed = 9;

// "" unless the controller `label` ended with kControllerExitFell; then a sentence with its own
// words on the fall (the last "the robot fell ..." line of its output file `output`).
std::string ControllerFall(const std::string& label, int exit_code, const std::string& output);

// The files of a run folder that summary.json lists under "files" (name -> file in the folder):
// log, plot and sim_summary always; walk (walk.csv, the walk controller's log, written through
// the placeholder {out}, see commands.h) when `out_dir` holds it.
std::map<std::string, std::string> OutputFiles(const std::string& out_dir);

}  // namespace ohrp::runner
