// Scenario runs (see runner.h): the implicit checks' verdicts, and a run as its stages in order
// (scenario_run.h).
#include "runner/runner.h"

#include <signal.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scenario_run.h"
#include "sim_host/exit_codes.h"

namespace fs = std::filesystem;

namespace ohrp::runner {
namespace {

std::atomic<int> g_signal{0};
void OnSignal(int sig) { g_signal.store(sig); }

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

int SignalReceived() { return g_signal.load(); }

int RunScenario(const Scenario& s, const RunOptions& o) {
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  ScenarioRun run(s, o);
  if (const int code = run.SetUp(); code >= 0) return code;
  if (const int code = run.Start(); code >= 0) return code;
  run.Supervise();
  run.StopControllers();
  run.Judge();
  run.WriteSummary();
  run.Plot();
  return run.Report();
}

}  // namespace ohrp::runner
