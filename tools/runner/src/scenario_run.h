// RunScenario's stages (runner.h): one scenario run as an object with one method per stage:
//   SetUp       the files it needs exist, its names are the model's, the run folder, the
//               processes' command lines (nothing started yet)
//   Start       sim_host, then, once its segment is sized, the controllers
//   Supervise   until sim_host ends: a signal, the wall-time limit, every controller refusing
//   StopControllers  they see the producer stop and end by themselves, else are stopped
//   Judge       the implicit checks (the processes, a fall) and the scenario's checks on the log
//   WriteSummary, Plot, Report   summary.json, plot.png and the table of checks
// scenario_run.cc has the run, scenario_verdict.cc the verdict; runner.cc runs them in order.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "children.h"
#include "runner/runner.h"

namespace ohrp::runner {

// the signal (SIGINT, SIGTERM) that asked the run to stop, 0 when none (runner.cc)
int SignalReceived();

// the reason a controller gave for exit 9 (its "FAILED: ..." line) or for refusing to run (exit
// 2 or 3: its first line, cut short); "" otherwise (runner.cc)
std::string ControllerFailure(int exit_code, const std::string& output);

class ScenarioRun {
 public:
  ScenarioRun(const Scenario& s, const RunOptions& o) : s_(s), o_(o) {}

  int SetUp();  // -1 to go on, else the exit code (kRunUsage)
  int Start();  // -1 to go on, else the exit code
  void Supervise();
  void StopControllers();
  void Judge();
  void WriteSummary();
  void Plot();
  int Report();  // the exit code

 private:
  std::string MissingFiles();
  bool SegmentSized() const;
  void SupervisionStep();
  void AddProcessChecks();
  void AddScenarioChecks();

  const Scenario& s_;
  const RunOptions& o_;
  std::string scene_, out_, out_abs_, segment_;
  std::vector<std::string> programs_;  // the controllers' executables
  Child sim_;
  std::vector<Child> ctl_;
  double t0_ = 0, wall_limit_ = 0, wall_ = 0;
  std::string aborted_;  // why the run was stopped, if it was
  int interrupted_ = 0;  // the signal that stopped it
  // the verdict
  nlohmann::json sim_summary_ = nlohmann::json::object();
  std::vector<CheckResult> results_;
  bool have_log_ = false;
  bool passed_ = false;
  std::string verdict_;
  nlohmann::json summary_;
};

}  // namespace ohrp::runner
