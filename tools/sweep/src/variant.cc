// One variant: the sweep folder's layout (Prepare), one run of ohrp_run under the time limit
// (RunVariant) and the Slurm array task's entry (RunSlurmTask). See sweep.h.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "stop.h"
#include "sweep/sweep.h"
#include "shm_bridge/clock.h"

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

constexpr double kKillGrace = 5.0;  // [s] from SIGTERM to SIGKILL of a variant's processes
constexpr int kTimedOut = 124;      // RunVariant's code for a variant killed at its time limit

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::string Host() {
  char b[256] = {};
  gethostname(b, sizeof(b) - 1);
  return b;
}

bool WriteFile(const std::string& path, const std::string& text, std::string* error) {
  std::ofstream out(path);
  out << text;
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

}  // namespace

std::string VariantDir(const std::string& out_dir, int id) {
  char b[32];
  std::snprintf(b, sizeof(b), "v%03d", id);
  return (fs::path(out_dir) / "variants" / b).string();
}

std::string SegmentName(const std::string& tag, int id) {
  return "sweep_" + tag + "_" + std::to_string(id);
}

bool Prepare(const SweepSpec& spec, const std::string& out_dir, std::string* error) {
  std::error_code ec;
  fs::remove_all(fs::path(out_dir) / "variants", ec);
  for (const char* f : {"sweep.csv", "table.md", "sweep.json"}) fs::remove(fs::path(out_dir) / f, ec);
  fs::create_directories(fs::path(out_dir) / "variants", ec);
  if (ec) {
    *error = "cannot create the sweep folder '" + out_dir + "': " + ec.message();
    return false;
  }
  // sweep.json: the sweep expanded, what a reader needs without the sweep file
  nlohmann::json j;
  j["name"] = spec.name;
  j["sweep_file"] = spec.file;
  j["scenario_file"] = spec.scenario_file;
  j["time_limit"] = spec.time_limit;
  j["parameters"] = nlohmann::json::array();
  for (const auto& p : spec.parameters) {
    nlohmann::json values = nlohmann::json::array();
    for (const auto& v : p.values) values.push_back(v.text);
    j["parameters"].push_back({{"key", p.key}, {"values", values}, {"log_scale", p.log_scale}});
    if (!p.draw.empty()) j["parameters"].back()["draw"] = p.draw;
  }
  j["variants"] = spec.variants.size();
  j["plots"] = nlohmann::json::array();
  for (const auto& p : spec.plots) j["plots"].push_back({{"check", p.check}, {"against", p.against}});
  if (!WriteFile((fs::path(out_dir) / "sweep.json").string(), j.dump(2) + "\n", error)) return false;

  // per variant: its scenario and what it is
  for (size_t i = 0; i < spec.variants.size(); ++i) {
    const Variant& v = spec.variants[i];
    const std::string dir = VariantDir(out_dir, v.id);
    fs::create_directories(dir, ec);
    nlohmann::json vj;
    vj["id"] = v.id;
    vj["time_limit"] = spec.time_limit;
    vj["value_index"] = v.value_index;  // into sweep.json's values (LoadSweepFolder)
    vj["parameters"] = nlohmann::json::object();
    for (size_t p = 0; p < spec.parameters.size(); ++p)
      vj["parameters"][spec.parameters[p].key] = spec.parameters[p].values[v.value_index[p]].text;
    if (ec || !WriteFile(dir + "/scenario.yaml", spec.variant_scenarios[i], error) ||
        !WriteFile(dir + "/variant.json", vj.dump(2) + "\n", error)) {
      if (error->empty()) *error = "cannot create " + dir + ": " + ec.message();
      return false;
    }
  }
  return true;
}

int RunVariant(const std::string& variant_dir, const std::string& segment, double time_limit,
               const RunContext& ctx) {
  const std::string dir = fs::absolute(variant_dir).lexically_normal().string();
  const std::string program = ctx.bin_dir + "/ohrp_run";
  std::vector<std::string> argv = {program, dir + "/scenario.yaml", "--out", dir + "/run",
                                   "--quiet", "--segment", segment};
  if (!ctx.run_plots) argv.push_back("--no-plot");
  fs::remove_all(dir + "/run");
  fs::remove(dir + "/status.json");

  // ohrp_run in its own process group, so that the group (sim_host, controllers) can be ended
  const double t0 = ohrp::MonotonicSeconds();
  const std::time_t started = std::time(nullptr);
  // everything the child needs is made before the fork: other threads (the local executor's
  // workers) may hold the allocator's lock at that moment, so the child allocates nothing
  const std::string output = dir + "/ohrp_run.out";
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  const int fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    if (fd >= 0) {
      dup2(fd, 1);  // dup2 clears O_CLOEXEC on the copies
      dup2(fd, 2);
    }
    if (chdir(ctx.source_dir.c_str()) != 0) _exit(126);
    execv(args[0], args.data());
    static const char kCannot[] = "ohrp_sweep: cannot execute ohrp_run (build it: cmake --build build)\n";
    if (write(2, kCannot, sizeof(kCannot) - 1) < 0) _exit(127);
    _exit(127);
  }
  if (fd >= 0) ::close(fd);
  int code = -1;
  bool timed_out = false, cancelled = false;
  if (pid > 0) {
    setpgid(pid, pid);
    double term_at = -1;  // when SIGTERM went to the group
    int status = 0;
    while (true) {
      const pid_t r = waitpid(pid, &status, WNOHANG);
      if (r == pid) {
        code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      const double now = ohrp::MonotonicSeconds();
      if (term_at < 0 && (now - t0 > time_limit || StopRequested())) {
        timed_out = !StopRequested();
        cancelled = !timed_out;
        term_at = now;
        killpg(pid, SIGTERM);
      } else if (term_at >= 0 && now - term_at > kKillGrace) {
        killpg(pid, SIGKILL);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // whatever is left of the group (a controller that ignored SIGTERM)
    killpg(pid, SIGKILL);
  }
  const double wall = ohrp::MonotonicSeconds() - t0;

  nlohmann::json j;
  j["exit_code"] = code;
  j["wall_time"] = wall;
  j["time_limit"] = time_limit;
  j["killed_at_time_limit"] = timed_out;
  j["cancelled"] = cancelled;
  j["started"] = static_cast<long long>(started);
  j["host"] = Host();
  j["segment"] = segment;
  j["command"] = argv;
  if (pid < 0) j["error"] = "fork failed";
  j["slurm_job_id"] = Env("SLURM_JOB_ID");
  j["slurm_array_job_id"] = Env("SLURM_ARRAY_JOB_ID");
  j["slurm_array_task_id"] = Env("SLURM_ARRAY_TASK_ID");  // the variant less its chunk's offset
  std::string error;
  // written to a temporary name first: a reader never sees half a status
  if (WriteFile(dir + "/status.json.tmp", j.dump(2) + "\n", &error))
    fs::rename(dir + "/status.json.tmp", dir + "/status.json");
  else
    std::fprintf(stderr, "ohrp_sweep: %s\n", error.c_str());
  return timed_out ? kTimedOut : code;
}

int RunSlurmTask(const std::string& out_dir, const RunContext& ctx, int offset) {
  const std::string task = Env("SLURM_ARRAY_TASK_ID"), job = Env("SLURM_ARRAY_JOB_ID");
  if (task.empty() || job.empty() || task.find_first_not_of("0123456789") != std::string::npos) {
    std::fprintf(stderr, "ohrp_sweep: --task runs inside a Slurm array job (SLURM_ARRAY_TASK_ID and "
                         "SLURM_ARRAY_JOB_ID unset); use --slurm to submit one\n");
    return 2;
  }
  const int id = offset + std::stoi(task);
  const std::string dir = VariantDir(out_dir, id);
  nlohmann::json v;
  try {
    std::ifstream(dir + "/variant.json") >> v;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ohrp_sweep: %s/variant.json: %s (not a prepared sweep folder?)\n", dir.c_str(), e.what());
    return 2;
  }
  InstallStopHandlers();
  return RunVariant(dir, SegmentName(job, id), v.value("time_limit", 600.0), ctx);
}

}  // namespace ohrp::sweep
