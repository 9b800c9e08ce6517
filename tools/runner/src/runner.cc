// Scenario runs: processes side by side, checks, summary and plot (see runner.h).
#include "runner/runner.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "children.h"
#include "runner/checks.h"
#include "runner/commands.h"
#include "shm_bridge/clock.h"
#include "sim_host/host.h"
#include "tool_process/run_command.h"

namespace fs = std::filesystem;

namespace ohrp::runner {
namespace {

std::atomic<int> g_signal{0};
void OnSignal(int sig) { g_signal.store(sig); }

std::string Resolve(const std::string& path, const std::string& root) {
  if (path.empty() || path[0] == '/') return path;
  return (fs::path(root) / path).lexically_normal().string();
}

std::string Stamp() {
  std::time_t t = std::time(nullptr);
  char b[32];
  std::strftime(b, sizeof(b), "%Y%m%d-%H%M%S", std::localtime(&t));
  return b;
}

// "scenario 'FILE': line N: " (no line for a scenario built in code)
std::string Where(const Scenario& s, int line) {
  return line > 0 ? "scenario '" + s.file + "': line " + std::to_string(line) + ": " : "";
}

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

// true when the sim_host summary at `path` says the run ended ("running" until its end)
bool RanToAnEnd(const std::string& path) {
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  return j.is_object() && j.contains("outcome") && j["outcome"] != "running";
}

}  // namespace

CheckResult SimHostCompleted(const Scenario& s, int exit_code, const nlohmann::json& sim,
                             const std::string& aborted, const std::string& controller_fall) {
  std::string detail = sim.value("outcome", std::string("no summary"));
  if (const std::string d = sim.value("detail", std::string()); !d.empty()) detail += ": " + d;
  const nlohmann::json fall = sim.contains("fall") ? sim["fall"] : nlohmann::json();
  const bool sim_fell = exit_code == sim::kExitFell && fall.is_object();
  // a fall seen first by a controller's own sensors (it left, and sim_host lost its controller)
  const bool fell = sim_fell || !controller_fall.empty();
  CheckResult r{"sim_host_completed", exit_code == 0 && !fell, static_cast<double>(exit_code),
                "exit code", "== 0", detail};
  char at[64] = "";
  if (sim_fell) {
    std::snprintf(at, sizeof(at), "fell at t=%.3f s (cycle %llu): ", fall.value("time", 0.0),
                  static_cast<unsigned long long>(fall.value("cycle", 0ull)));
    r.detail = at + fall.value("cause", std::string("?"));
  } else if (fell) {
    r.detail = controller_fall + " (sim_host: " + detail + ")";
  }
  if (s.expect_fall) {
    r.limit = "a fall (expect_fall: true)";
    r.passed = fell;
    if (fell) r.detail = "as expected: " + r.detail;
    else if (exit_code == 0) r.detail = "expected a fall and the robot did not fall (" + detail + ")";
  } else if (fell) {
    r.limit = "== 0, no fall (or expect_fall: true)";
  }
  if (!aborted.empty()) {
    r.passed = false;
    r.detail = aborted;
  }
  return r;
}

std::string ControllerFall(const std::string& label, int exit_code, const std::string& output) {
  if (exit_code != kControllerExitFell) return "";
  std::string said = "exit " + std::to_string(exit_code);
  std::ifstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.find("the robot fell") != std::string::npos) said = line;
  }
  return "controller '" + label + "' saw the robot fall: " + said;
}

// the reason a controller gave for exit 9 (kExitFailed): its "FAILED: ..." line, e.g. a motion
// the self-collision guard stopped; "" for another exit code or no such line
std::string ControllerFailure(int exit_code, const std::string& output) {
  // its own verdict (exit 9), or why it refused to run (exit 2 or 3: its first line, cut short)
  const bool refused = exit_code == 2 || exit_code == 3;
  if (exit_code != kControllerExitFailed && !refused) return "";
  std::string said;
  std::ifstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (refused && said.empty() && line.find("WARNING") == std::string::npos) said = line;
    if (!refused && line.find("FAILED: ") != std::string::npos) said = line;
  }
  if (said.size() > 160) said = said.substr(0, 157) + "...";
  return said;
}

std::map<std::string, std::string> OutputFiles(const std::string& out_dir) {
  std::map<std::string, std::string> files = {
      {"log", "log.csv"}, {"plot", "plot.png"}, {"sim_summary", "sim_summary.json"}};
  // the walk controller's own log, when it wrote one (its `--log "{out}/walk.csv"`)
  if (fs::exists(fs::path(out_dir) / "walk.csv")) files["walk"] = "walk.csv";
  return files;
}

int RunScenario(const Scenario& s, const RunOptions& o) {
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);

  //---------------- set-up ----------------
  // the files it needs exist, before anything is created or started
  const std::string scene = Resolve(s.scene, o.source_dir);
  std::vector<std::string> programs;
  std::string missing;
  if (!fs::exists(scene))
    missing += "\n  " + Where(s, s.scene_line) + "scene: '" + scene + "' does not exist";
  if (access((o.bin_dir + "/sim_host").c_str(), X_OK) != 0)
    missing += "\n  sim_host is not in " + o.bin_dir + " (build it: cmake --build build)";
  for (const auto& spec : s.controllers) {
    programs.push_back(spec.program.find('/') == std::string::npos
                           ? o.bin_dir + "/" + spec.program
                           : Resolve(spec.program, o.source_dir));
    if (access(programs.back().c_str(), X_OK) != 0)
      missing += "\n  " + Where(s, spec.line) + "controller program '" + programs.back() +
                 "' not found or not executable (a program in " + o.bin_dir + " or a path)";
  }
  if (!missing.empty()) {
    std::fprintf(stderr, "ohrp_run: cannot start the run:%s\n", missing.c_str());
    return kRunUsage;
  }
  // the names it gives are the model's (joints, sensors, bodies...)
  if (std::string why; !CheckScenarioNames(s, scene, &why)) {
    std::fprintf(stderr, "ohrp_run: %s\n", why.c_str());
    return kRunUsage;
  }
  const std::string out = o.out_dir.empty() ? "runs/" + s.name + "-" + Stamp() : o.out_dir;
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "ohrp_run: cannot create the output folder '%s': %s\n", out.c_str(),
                 ec.message().c_str());
    return kRunUsage;
  }
  const std::string out_abs = fs::absolute(out).string();
  if (std::string why; !s.joint_params.empty() &&
                       !WriteJointParams(s, out_abs + "/joint_params.yaml", &why)) {
    std::fprintf(stderr, "ohrp_run: %s\n", why.c_str());
    return kRunUsage;
  }
  const std::string segment =
      o.segment.empty() ? "run_" + s.name + "_" + std::to_string(getpid()) : o.segment;
  if (o.report)
    std::fprintf(stderr, "ohrp_run: scenario '%s' (%g s simulated) -> %s\n", s.name.c_str(),
                 s.duration, out.c_str());
  if (o.report && !s.description.empty()) std::fprintf(stderr, "ohrp_run: %s\n", s.description.c_str());

  Child sim;
  sim.label = "sim_host";
  sim.output = out_abs + "/sim_host.stderr";
  sim.argv = SimHostCommand(s, o.bin_dir + "/sim_host", scene, segment, out_abs);

  std::vector<Child> ctl(s.controllers.size());
  for (size_t i = 0; i < ctl.size(); ++i) {
    const std::string& prog = programs[i];
    ctl[i].label = fs::path(prog).filename().string() + (ctl.size() > 1 ? "#" + std::to_string(i) : "");
    ctl[i].output = out_abs + "/" + ctl[i].label + ".stderr";
    ctl[i].argv = ControllerCommand(s.controllers[i], prog, segment, out_abs);
  }

  //---------------- run ----------------
  std::string error;
  const double t0 = ohrp::MonotonicSeconds();
  const double wall_limit = s.wall_timeout > 0 ? s.wall_timeout : 60 + 30 * s.duration;
  std::string aborted;
  if (!Spawn(&sim, o.source_dir, &error)) {
    std::fprintf(stderr, "ohrp_run: %s\n", error.c_str());
    return kRunFailed;
  }
  // the segment exists once sim_host has loaded the scene and sized it (a controller started
  // between the creation and the sizing finds 0 bytes and refuses the segment)
  const std::string shm_file = "/dev/shm/ohrp_" + segment;
  const auto sized = [&] {
    std::error_code size_error;
    const auto size = fs::file_size(shm_file, size_error);
    return !size_error && size > 0;
  };
  while (!sized() && ohrp::MonotonicSeconds() - t0 < 30) {
    Reap(&sim);
    if (sim.done) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  Echo(&sim, o.echo);
  if (!sim.done) {
    for (auto& c : ctl) {
      if (!Spawn(&c, o.source_dir, &error)) aborted = error;
    }
  } else if (sim.exit_code == kRunUsage) {
    // sim_host refused a setting (a keyframe, contact parameters...): a bad scenario
    std::ifstream in(sim.output);
    std::string said, line;
    while (std::getline(in, line)) said += "\n  " + line;
    std::fprintf(stderr, "ohrp_run: %s: sim_host refused the scenario's settings (exit 2):%s\n",
                 s.file.c_str(), said.c_str());
    return kRunUsage;
  } else if (!RanToAnEnd(out_abs + "/sim_summary.json")) {
    aborted = "sim_host ended before it created its segment (exit " + std::to_string(sim.exit_code) + ")";
  }  // else it ran and ended before the segment was seen here (a robot that fell at once)
  int interrupted = 0;
  while (!sim.done) {
    if (g_signal.load() && !interrupted) {
      interrupted = g_signal.load();
      std::fprintf(stderr, "ohrp_run: interrupted; stopping the processes\n");
      Stop(&sim, SIGINT);
      for (auto& c : ctl) Stop(&c, SIGINT);
    }
    if (ohrp::MonotonicSeconds() - t0 > wall_limit && aborted.empty()) {
      aborted = "wall-time limit of " + Num(wall_limit) + " s reached";
      std::fprintf(stderr, "ohrp_run: %s; stopping sim_host\n", aborted.c_str());
      Stop(&sim, SIGTERM);
    }
    WaitAll({&sim}, ohrp::MonotonicSeconds() + 0.1, o.echo);
    for (auto& c : ctl) {
      Reap(&c);
      Echo(&c, o.echo);
    }
    // every controller refused to run (its command line or its files: exit 2 or 3, said on its
    // stderr): nothing will attach, so sim_host need not wait out its attach timeout
    const std::string refused = EveryControllerRefused(ctl);
    if (!refused.empty() && aborted.empty()) {
      aborted = "every controller refused to run (" + refused + ")";
      std::fprintf(stderr, "ohrp_run: %s; stopping sim_host\n", aborted.c_str());
      Stop(&sim, SIGTERM);
    }
  }
  // the controllers see the producer stop and end by themselves; give them a moment
  std::vector<Child*> rest;
  for (auto& c : ctl) rest.push_back(&c);
  WaitAll(rest, ohrp::MonotonicSeconds() + 5, o.echo);
  for (auto& c : ctl) Stop(&c, SIGTERM);
  WaitAll(rest, ohrp::MonotonicSeconds() + 2, o.echo);
  for (auto& c : ctl) Stop(&c, SIGKILL);
  WaitAll(rest, ohrp::MonotonicSeconds() + 1, o.echo);
  const double wall = ohrp::MonotonicSeconds() - t0;

  //---------------- checks ----------------
  nlohmann::json sim_summary = nlohmann::json::object();
  {
    std::ifstream in(out_abs + "/sim_summary.json");
    if (in) {
      try {
        in >> sim_summary;
      } catch (const std::exception&) {
      }
    }
  }
  std::vector<CheckResult> results;
  // implicit: the processes ended as they should, the robot did not fall (or fell as expected)
  std::string controller_fall;
  for (auto& c : ctl) {
    if (controller_fall.empty()) controller_fall = ControllerFall(c.label, c.exit_code, c.output);
  }
  results.push_back(SimHostCompleted(s, sim.exit_code, sim_summary, aborted, controller_fall));
  for (auto& c : ctl) {
    // a controller that saw the fall a scenario expects ended as it should
    const bool clean = c.exit_code == 0 || (s.expect_fall && c.exit_code == kControllerExitFell);
    const std::string failed = ControllerFailure(c.exit_code, c.output);
    results.push_back({c.label + "_exited_cleanly", clean, static_cast<double>(c.exit_code),
                       "exit code", s.expect_fall ? "== 0 or 8 (a fall)" : "== 0",
                       failed.empty() ? "see " + c.label + ".stderr" : failed});
  }
  datalog::Table log;
  bool have_log = log.Load(out_abs + "/log.csv", &error);
  if (have_log && log.rows() < 2) {  // a check on no simulated motion would pass vacuously
    have_log = false;
    error = "not judged: nothing was simulated (the log has " + std::to_string(log.rows()) + (log.rows() == 1 ? " row)" : " rows)");
  }
  for (const auto& spec : s.checks) {
    if (!have_log) {
      results.push_back({spec.type, false, 0, "", "", error});
      continue;
    }
    results.push_back(Evaluate(spec, log, sim_summary));
  }
  bool passed = !interrupted;
  for (const auto& r : results) passed = passed && r.passed;
  const std::string verdict = interrupted ? "interrupted" : passed ? "pass" : "fail";

  //---------------- summary, plot ----------------
  nlohmann::json j;
  j["scenario"] = s.name;
  j["scenario_file"] = s.file;
  j["verdict"] = verdict;
  j["sim_time"] = sim_summary.value("sim_time", 0.0);
  j["wall_time"] = wall;
  j["sim_host_wall_time"] = sim_summary.value("wall_time", 0.0);
  j["real_time_factor"] = sim_summary.value("real_time_factor", 0.0);
  j["steps"] = sim_summary.value("steps", 0);
  j["cycles"] = sim_summary.value("cycles", 0);
  j["physics_dt"] = sim_summary.value("physics_dt", 0.0);
  j["control_period"] = sim_summary.value("control_period", 0.0);
  j["checks"] = nlohmann::json::array();
  for (const auto& r : results) {
    j["checks"].push_back({{"name", r.name}, {"passed", r.passed}, {"value", r.value},
                           {"unit", r.unit}, {"limit", r.limit}, {"detail", r.detail}});
  }
  j["processes"] = nlohmann::json::array();
  j["processes"].push_back({{"name", "sim_host"}, {"exit_code", sim.exit_code}});
  for (auto& c : ctl) j["processes"].push_back({{"name", c.label}, {"exit_code", c.exit_code}});
  j["files"] = OutputFiles(out_abs);
  std::ofstream(out_abs + "/summary.json") << j.dump(2) << "\n";

  if (o.plot && have_log) {
    // an argument vector, no shell: the scenario's names are arguments, never commands
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string joints, torques;
    for (const auto& n : s.plot_joints) joints += (joints.empty() ? "" : ",") + n;
    for (const auto& n : s.plot_torques) torques += (torques.empty() ? "" : ",") + n;
    std::vector<std::string> cmd = {python, o.source_dir + "/tools/scripts/plot_run.py",
                                    out_abs + "/log.csv", out_abs + "/summary.json",
                                    out_abs + "/plot.png"};
    if (!joints.empty()) cmd.insert(cmd.end(), {"--joints", joints});
    if (!torques.empty()) cmd.insert(cmd.end(), {"--torques", torques});
    std::string why;
    if (tool::RunCommand(cmd, out_abs + "/plot.stderr", &why) != 0)
      std::fprintf(stderr, "ohrp_run: the plot could not be made (see %s/plot.stderr)\n", out.c_str());
  }

  // the verdict, readable
  if (!o.report) return interrupted ? kRunInterrupted : passed ? kRunPassed : kRunFailed;
  std::fprintf(stderr, "\n%-34s %-6s %14s  %s\n", "check", "result", "value", "limit / detail");
  for (const auto& r : results) {
    std::fprintf(stderr, "%-34s %-6s %14.6g  %s%s%s\n", r.name.c_str(), r.passed ? "pass" : "FAIL",
                 r.value, r.limit.c_str(), r.limit.empty() ? "" : "; ", r.detail.c_str());
  }
  // sim_host's own figure (simulated over its wall time while simulating) and the wall time the
  // processes took (start-up and waits for controllers included) are different things: both named
  std::fprintf(stderr,
               "\nscenario %s: %s (%.2f s simulated, sim_host at %.2fx real time while simulating; "
               "the processes ran %.2f s wall; %s)\n",
               s.name.c_str(), verdict == "pass" ? "PASS" : verdict == "fail" ? "FAIL" : "INTERRUPTED",
               j["sim_time"].get<double>(), j["real_time_factor"].get<double>(), wall, out.c_str());
  if (interrupted) return kRunInterrupted;
  return passed ? kRunPassed : kRunFailed;
}

}  // namespace ohrp::runner
