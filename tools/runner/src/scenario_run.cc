// A scenario's run: set-up, the processes started side by side and supervised (see scenario_run.h).
#include "scenario_run.h"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <thread>

#include "runner/commands.h"
#include "shm_bridge/clock.h"

namespace fs = std::filesystem;

namespace ohrp::runner {
namespace {

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

//---------------- set-up ----------------

int ScenarioRun::SetUp() {
  // the files it needs exist, before anything is created or started
  scene_ = Resolve(s_.scene, o_.source_dir);
  if (const std::string missing = MissingFiles(); !missing.empty()) {
    std::fprintf(stderr, "ohrp_run: cannot start the run:%s\n", missing.c_str());
    return kRunUsage;
  }
  // the names it gives are the model's (joints, sensors, bodies...)
  if (std::string why; !CheckScenarioNames(s_, scene_, &why)) {
    std::fprintf(stderr, "ohrp_run: %s\n", why.c_str());
    return kRunUsage;
  }
  out_ = o_.out_dir.empty() ? "runs/" + s_.name + "-" + Stamp() : o_.out_dir;
  std::error_code ec;
  fs::create_directories(out_, ec);
  if (ec) {
    std::fprintf(stderr, "ohrp_run: cannot create the output folder '%s': %s\n", out_.c_str(),
                 ec.message().c_str());
    return kRunUsage;
  }
  out_abs_ = fs::absolute(out_).string();
  if (std::string why; !s_.joint_params.empty() &&
                       !WriteJointParams(s_, out_abs_ + "/joint_params.yaml", &why)) {
    std::fprintf(stderr, "ohrp_run: %s\n", why.c_str());
    return kRunUsage;
  }
  segment_ = o_.segment.empty() ? "run_" + s_.name + "_" + std::to_string(getpid()) : o_.segment;
  if (o_.report)
    std::fprintf(stderr, "ohrp_run: scenario '%s' (%g s simulated) -> %s\n", s_.name.c_str(),
                 s_.duration, out_.c_str());
  if (o_.report && !s_.description.empty()) std::fprintf(stderr, "ohrp_run: %s\n", s_.description.c_str());

  sim_.label = "sim_host";
  sim_.output = out_abs_ + "/sim_host.stderr";
  sim_.argv = SimHostCommand(s_, o_.bin_dir + "/sim_host", scene_, segment_, out_abs_);
  ctl_.resize(s_.controllers.size());
  for (size_t i = 0; i < ctl_.size(); ++i) {
    const std::string& prog = programs_[i];
    ctl_[i].label = fs::path(prog).filename().string() + (ctl_.size() > 1 ? "#" + std::to_string(i) : "");
    ctl_[i].output = out_abs_ + "/" + ctl_[i].label + ".stderr";
    ctl_[i].argv = ControllerCommand(s_.controllers[i], prog, segment_, out_abs_);
  }
  return -1;
}

// the scene, sim_host and the controllers' programs (resolved into programs_): "" or a line each
std::string ScenarioRun::MissingFiles() {
  std::string missing;
  if (!fs::exists(scene_))
    missing += "\n  " + Where(s_, s_.scene_line) + "scene: '" + scene_ + "' does not exist";
  if (access((o_.bin_dir + "/sim_host").c_str(), X_OK) != 0)
    missing += "\n  sim_host is not in " + o_.bin_dir + " (build it: cmake --build build)";
  for (const auto& spec : s_.controllers) {
    programs_.push_back(spec.program.find('/') == std::string::npos
                            ? o_.bin_dir + "/" + spec.program
                            : Resolve(spec.program, o_.source_dir));
    if (access(programs_.back().c_str(), X_OK) != 0)
      missing += "\n  " + Where(s_, spec.line) + "controller program '" + programs_.back() +
                 "' not found or not executable (a program in " + o_.bin_dir + " or a path)";
  }
  return missing;
}

//---------------- run ----------------

int ScenarioRun::Start() {
  std::string error;
  t0_ = ohrp::MonotonicSeconds();
  wall_limit_ = s_.wall_timeout > 0 ? s_.wall_timeout : 60 + 30 * s_.duration;
  if (!Spawn(&sim_, o_.source_dir, &error)) {
    std::fprintf(stderr, "ohrp_run: %s\n", error.c_str());
    return kRunFailed;
  }
  // the segment exists once sim_host has loaded the scene and sized it (a controller started
  // between the creation and the sizing finds 0 bytes and refuses the segment)
  while (!SegmentSized() && ohrp::MonotonicSeconds() - t0_ < 30) {
    Reap(&sim_);
    if (sim_.done) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  Echo(&sim_, o_.echo);
  if (!sim_.done) {
    for (auto& c : ctl_) {
      if (!Spawn(&c, o_.source_dir, &error)) aborted_ = error;
    }
  } else if (sim_.exit_code == kRunUsage) {
    // sim_host refused a setting (a keyframe, contact parameters...): a bad scenario
    std::ifstream in(sim_.output);
    std::string said, line;
    while (std::getline(in, line)) said += "\n  " + line;
    std::fprintf(stderr, "ohrp_run: %s: sim_host refused the scenario's settings (exit 2):%s\n",
                 s_.file.c_str(), said.c_str());
    return kRunUsage;
  } else if (!RanToAnEnd(out_abs_ + "/sim_summary.json")) {
    aborted_ = "sim_host ended before it created its segment (exit " + std::to_string(sim_.exit_code) + ")";
  }  // else it ran and ended before the segment was seen here (a robot that fell at once)
  return -1;
}

bool ScenarioRun::SegmentSized() const {
  std::error_code size_error;
  const auto size = fs::file_size("/dev/shm/ohrp_" + segment_, size_error);
  return !size_error && size > 0;
}

void ScenarioRun::Supervise() {
  while (!sim_.done) SupervisionStep();
}

// one round of supervision: a signal, the wall-time limit, the processes' output and ends
void ScenarioRun::SupervisionStep() {
  if (SignalReceived() && !interrupted_) {
    interrupted_ = SignalReceived();
    std::fprintf(stderr, "ohrp_run: interrupted; stopping the processes\n");
    Stop(&sim_, SIGINT);
    for (auto& c : ctl_) Stop(&c, SIGINT);
  }
  if (ohrp::MonotonicSeconds() - t0_ > wall_limit_ && aborted_.empty()) {
    aborted_ = "wall-time limit of " + Num(wall_limit_) + " s reached";
    std::fprintf(stderr, "ohrp_run: %s; stopping sim_host\n", aborted_.c_str());
    Stop(&sim_, SIGTERM);
  }
  WaitAll({&sim_}, ohrp::MonotonicSeconds() + 0.1, o_.echo);
  for (auto& c : ctl_) {
    Reap(&c);
    Echo(&c, o_.echo);
  }
  // every controller refused to run (its command line or its files: exit 2 or 3, said on its
  // stderr): nothing will attach, so sim_host need not wait out its attach timeout
  const std::string refused = EveryControllerRefused(ctl_);
  if (!refused.empty() && aborted_.empty()) {
    aborted_ = "every controller refused to run (" + refused + ")";
    std::fprintf(stderr, "ohrp_run: %s; stopping sim_host\n", aborted_.c_str());
    Stop(&sim_, SIGTERM);
  }
}

// the controllers see the producer stop and end by themselves; given a moment, then stopped
void ScenarioRun::StopControllers() {
  std::vector<Child*> rest;
  for (auto& c : ctl_) rest.push_back(&c);
  WaitAll(rest, ohrp::MonotonicSeconds() + 5, o_.echo);
  for (auto& c : ctl_) Stop(&c, SIGTERM);
  WaitAll(rest, ohrp::MonotonicSeconds() + 2, o_.echo);
  for (auto& c : ctl_) Stop(&c, SIGKILL);
  WaitAll(rest, ohrp::MonotonicSeconds() + 1, o_.echo);
  wall_ = ohrp::MonotonicSeconds() - t0_;
}

}  // namespace ohrp::runner
