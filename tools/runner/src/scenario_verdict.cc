// A scenario's verdict: its checks, summary.json, the plot and the table (see scenario_run.h).
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runner/checks.h"
#include "scenario_run.h"
#include "tool_process/run_command.h"

namespace fs = std::filesystem;

namespace ohrp::runner {

//---------------- checks ----------------

void ScenarioRun::Judge() {
  {
    std::ifstream in(out_abs_ + "/sim_summary.json");
    if (in) {
      try {
        in >> sim_summary_;
      } catch (const std::exception&) {
      }
    }
  }
  AddProcessChecks();
  AddScenarioChecks();
  passed_ = !interrupted_;
  for (const auto& r : results_) passed_ = passed_ && r.passed;
  verdict_ = interrupted_ ? "interrupted" : passed_ ? "pass" : "fail";
}

// implicit: the processes ended as they should, the robot did not fall (or fell as expected)
void ScenarioRun::AddProcessChecks() {
  std::string controller_fall;
  for (auto& c : ctl_) {
    if (controller_fall.empty()) controller_fall = ControllerFall(c.label, c.exit_code, c.output);
  }
  results_.push_back(SimHostCompleted(s_, sim_.exit_code, sim_summary_, aborted_, controller_fall));
  for (auto& c : ctl_) {
    // a controller that saw the fall a scenario expects ended as it should
    const bool clean = c.exit_code == 0 || (s_.expect_fall && c.exit_code == kControllerExitFell);
    const std::string failed = ControllerFailure(c.exit_code, c.output);
    results_.push_back({c.label + "_exited_cleanly", clean, static_cast<double>(c.exit_code),
                        "exit code", s_.expect_fall ? "== 0 or 8 (a fall)" : "== 0",
                        failed.empty() ? "see " + c.label + ".stderr" : failed});
  }
}

// the scenario's checks, on the simulated state in the log
void ScenarioRun::AddScenarioChecks() {
  datalog::Table log;
  std::string error;
  have_log_ = log.Load(out_abs_ + "/log.csv", &error);
  if (have_log_ && log.rows() < 2) {  // a check on no simulated motion would pass vacuously
    have_log_ = false;
    error = "not judged: nothing was simulated (the log has " + std::to_string(log.rows()) +
            (log.rows() == 1 ? " row)" : " rows)");
  }
  for (const auto& spec : s_.checks) {
    if (!have_log_) {
      results_.push_back({spec.type, false, 0, "", "", error});
      continue;
    }
    results_.push_back(Evaluate(spec, log, sim_summary_));
  }
}

//---------------- summary, plot, table ----------------

void ScenarioRun::WriteSummary() {
  nlohmann::json& j = summary_;
  j["scenario"] = s_.name;
  j["scenario_file"] = s_.file;
  j["verdict"] = verdict_;
  j["sim_time"] = sim_summary_.value("sim_time", 0.0);
  j["wall_time"] = wall_;
  j["sim_host_wall_time"] = sim_summary_.value("wall_time", 0.0);
  j["real_time_factor"] = sim_summary_.value("real_time_factor", 0.0);
  j["steps"] = sim_summary_.value("steps", 0);
  j["cycles"] = sim_summary_.value("cycles", 0);
  j["physics_dt"] = sim_summary_.value("physics_dt", 0.0);
  j["control_period"] = sim_summary_.value("control_period", 0.0);
  j["checks"] = nlohmann::json::array();
  for (const auto& r : results_) {
    j["checks"].push_back({{"name", r.name}, {"passed", r.passed}, {"value", r.value},
                           {"unit", r.unit}, {"limit", r.limit}, {"detail", r.detail}});
  }
  j["processes"] = nlohmann::json::array();
  j["processes"].push_back({{"name", "sim_host"}, {"exit_code", sim_.exit_code}});
  for (auto& c : ctl_) j["processes"].push_back({{"name", c.label}, {"exit_code", c.exit_code}});
  j["files"] = OutputFiles(out_abs_);
  std::ofstream(out_abs_ + "/summary.json") << j.dump(2) << "\n";
}

void ScenarioRun::Plot() {
  if (!o_.plot || !have_log_) return;
  // an argument vector, no shell: the scenario's names are arguments, never commands
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  std::string joints, torques;
  for (const auto& n : s_.plot_joints) joints += (joints.empty() ? "" : ",") + n;
  for (const auto& n : s_.plot_torques) torques += (torques.empty() ? "" : ",") + n;
  std::vector<std::string> cmd = {python, o_.source_dir + "/tools/scripts/plot_run.py",
                                  out_abs_ + "/log.csv", out_abs_ + "/summary.json",
                                  out_abs_ + "/plot.png"};
  if (!joints.empty()) cmd.insert(cmd.end(), {"--joints", joints});
  if (!torques.empty()) cmd.insert(cmd.end(), {"--torques", torques});
  std::string why;
  if (tool::RunCommand(cmd, out_abs_ + "/plot.stderr", &why) != 0)
    std::fprintf(stderr, "ohrp_run: the plot could not be made (see %s/plot.stderr)\n", out_.c_str());
}

// the verdict, readable; the exit code
int ScenarioRun::Report() {
  const int code = interrupted_ ? kRunInterrupted : passed_ ? kRunPassed : kRunFailed;
  if (!o_.report) return code;
  std::fprintf(stderr, "\n%-34s %-6s %14s  %s\n", "check", "result", "value", "limit / detail");
  for (const auto& r : results_) {
    std::fprintf(stderr, "%-34s %-6s %14.6g  %s%s%s\n", r.name.c_str(), r.passed ? "pass" : "FAIL",
                 r.value, r.limit.c_str(), r.limit.empty() ? "" : "; ", r.detail.c_str());
  }
  // sim_host's own figure (simulated over its wall time while simulating) and the wall time the
  // processes took (start-up and waits for controllers included) are different things: both named
  std::fprintf(stderr,
               "\nscenario %s: %s (%.2f s simulated, sim_host at %.2fx real time while simulating; "
               "the processes ran %.2f s wall; %s)\n",
               s_.name.c_str(), verdict_ == "pass" ? "PASS" : verdict_ == "fail" ? "FAIL" : "INTERRUPTED",
               summary_["sim_time"].get<double>(), summary_["real_time_factor"].get<double>(), wall_,
               out_.c_str());
  return code;
}

}  // namespace ohrp::runner
