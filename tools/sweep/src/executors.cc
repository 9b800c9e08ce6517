// The executors (see sweep.h): local worker threads, or a Slurm array job polled until it ends;
// both prepare the same folder and gather it with the same code.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include "stop.h"
#include "sweep/sweep.h"
#include "shm_bridge/clock.h"

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

constexpr double kSqueueGiveUp = 300;  // [s] of squeue failing in a row before giving up

std::string Describe(const SweepSpec& s, const Variant& v) {
  std::string d;
  for (size_t p = 0; p < s.parameters.size(); ++p)
    d += (p ? " " : "") + s.parameters[p].key + "=" + s.parameters[p].values[v.value_index[p]].text;
  return d;
}

// the status one finished variant got, for a progress line
std::string StatusOf(const SweepSpec& spec, const std::string& out_dir, int id) {
  SweepSpec one;  // the parameters and this variant only (not every variant's scenario)
  one.parameters = spec.parameters;
  one.variants = {spec.variants[id]};
  const auto r = Gather(one, out_dir);
  return r[0].status + (r[0].status == "pass" ? "" : " (" + r[0].detail.substr(0, 100) + ")");
}

//---------------- local ----------------

void RunLocal(const SweepSpec& spec, const Executor& ex, const std::string& out_dir,
              const RunContext& ctx, SweepOutcome* outcome, std::map<int, std::string>* states) {
  const size_t n = spec.variants.size();
  unsigned jobs = ex.jobs > 0 ? static_cast<unsigned>(ex.jobs) : std::max(1u, std::thread::hardware_concurrency());
  jobs = std::min<unsigned>(jobs, static_cast<unsigned>(n));
  if (ex.progress)
    std::fprintf(stderr, "ohrp_sweep: %zu variants of %s, %u at a time, time limit %g s each -> %s\n", n,
                 spec.scenario_file.c_str(), jobs, spec.time_limit, out_dir.c_str());
  std::atomic<size_t> next{0};
  std::atomic<int> done{0};
  std::mutex mutex;
  const std::string tag = std::to_string(getpid());
  auto work = [&] {
    for (size_t i; (i = next++) < n;) {
      const Variant& v = spec.variants[i];
      if (StopRequested()) {
        std::lock_guard<std::mutex> lock(mutex);
        (*states)[v.id] = "CANCELLED: the sweep was interrupted before the variant started";
        continue;
      }
      const double t0 = ohrp::MonotonicSeconds();
      RunVariant(VariantDir(out_dir, v.id), SegmentName(tag, v.id), spec.time_limit, ctx);
      const int k = ++done;
      if (ex.progress) {
        const std::string status = StatusOf(spec, out_dir, v.id);
        std::lock_guard<std::mutex> lock(mutex);
        std::fprintf(stderr, "ohrp_sweep: [%d/%zu] v%03d %s: %s, %.1f s\n", k, n, v.id,
                     Describe(spec, v).c_str(), status.c_str(), ohrp::MonotonicSeconds() - t0);
      }
    }
  };
  std::vector<std::thread> workers;
  for (unsigned k = 0; k < jobs; ++k) workers.emplace_back(work);
  for (auto& w : workers) w.join();
  outcome->interrupted = StopRequested();
}

//---------------- slurm ----------------

std::string Quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// runs a command line (sh -c) and captures its stdout; its exit code
int Capture(const std::vector<std::string>& argv, std::string* out) {
  std::string cmd;
  for (const auto& a : argv) {
    if (!cmd.empty()) cmd += ' ';
    cmd += Quote(a);
  }
  cmd += " 2>&1";
  out->clear();
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return -1;
  char b[4096];
  for (size_t k; (k = std::fread(b, 1, sizeof(b), p)) > 0;) out->append(b, k);
  const int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128;
}

std::string Trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s;
}

int CountStatuses(const SweepSpec& spec, const std::string& out_dir) {
  int k = 0;
  for (const auto& v : spec.variants) k += fs::exists(VariantDir(out_dir, v.id) + "/status.json");
  return k;
}

// the task ids of an array record: "4", or a range of tasks never started as their own jobs
// ("[2-5]", "2-3,7", "0-8%2" with its limit of running tasks)
std::vector<int> TaskIds(std::string spec) {
  std::vector<int> ids;
  spec = spec.substr(0, spec.find('%'));
  std::string clean;
  for (char c : spec)
    if (c != '[' && c != ']') clean += c;
  std::istringstream in(clean);
  for (std::string part; std::getline(in, part, ',');) {
    const auto dash = part.find('-');
    const std::string a = part.substr(0, dash), b = dash == std::string::npos ? a : part.substr(dash + 1);
    if (a.empty() || b.empty() || (a + b).find_first_not_of("0123456789") != std::string::npos) continue;
    for (int k = std::stoi(a); k <= std::stoi(b); ++k) ids.push_back(k);
  }
  return ids;
}

// the array's task states: sacct when accounting is on, else the controller's memory
// (scontrol keeps finished jobs for MinJobAge); "" for a task neither knows
std::map<int, std::string> TaskStates(const std::string& job) {
  std::map<int, std::string> states;
  std::string out;
  if (Capture({"sacct", "-n", "-P", "-X", "-j", job, "-o", "JobID,State"}, &out) == 0) {
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) {
      const auto us = line.find('_'), bar = line.find('|');
      if (us == std::string::npos || bar == std::string::npos || bar < us) continue;
      for (int task : TaskIds(line.substr(us + 1, bar - us - 1))) states[task] = Trim(line.substr(bar + 1));
    }
    if (!states.empty()) return states;
  }
  if (Capture({"scontrol", "-o", "show", "job", job}, &out) == 0) {
    std::istringstream in(out);
    for (std::string line; std::getline(in, line);) {
      const auto t = line.find("ArrayTaskId="), s = line.find("JobState=");
      if (t == std::string::npos || s == std::string::npos) continue;
      for (int task : TaskIds(line.substr(t + 12, line.find(' ', t) - t - 12)))
        states[task] = line.substr(s + 9, line.find(' ', s) - s - 9);
    }
  }
  return states;
}

// whether the job still has tasks pending or running: 1 yes, 0 no, -1 squeue failed (*why)
int JobActive(const std::string& job, std::string* why) {
  std::string out;
  const int rc = Capture({"squeue", "-h", "-j", job, "-o", "%T"}, &out);
  if (rc != 0) {
    if (out.find("Invalid job id") != std::string::npos) return 0;  // gone from the queue: done
    *why = Trim(out);
    return -1;
  }
  return Trim(out).empty() ? 0 : 1;
}

void RunSlurm(const SweepSpec& spec, const Executor& ex, const std::string& out_dir,
              const RunContext& ctx, SweepOutcome* outcome, std::map<int, std::string>* states) {
  const size_t n = spec.variants.size();
  // the task script: ohrp_sweep --task on this folder (a shared filesystem on a real cluster)
  const std::string slurm_dir = out_dir + "/slurm";
  fs::create_directories(slurm_dir);
  const std::string script = slurm_dir + "/task.sh";
  {
    FILE* f = std::fopen(script.c_str(), "w");
    if (!f) {
      outcome->error = "cannot write " + script;
      return;
    }
    std::fprintf(f,
                 "#!/bin/sh\n# one variant of sweep %s: variants/v<SLURM_ARRAY_TASK_ID> (ohrp_sweep --task)\n"
                 "exec %s --task %s%s\n",
                 spec.name.c_str(), Quote(ctx.bin_dir + "/ohrp_sweep").c_str(), Quote(out_dir).c_str(),
                 ctx.run_plots ? " --run-plots" : "");
    std::fclose(f);
    fs::permissions(script, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                fs::perms::others_read | fs::perms::others_exec);
  }
  std::string array = "--array=0-" + std::to_string(n - 1);
  if (ex.max_running > 0) array += "%" + std::to_string(ex.max_running);
  const int minutes = static_cast<int>(std::ceil((spec.time_limit + 60) / 60));
  std::vector<std::string> argv = {"sbatch", "--parsable", array, "--job-name=ohrp-sweep-" + spec.name,
                                   "--output=" + slurm_dir + "/task_%a.out", "--chdir=" + ctx.source_dir,
                                   "--ntasks=1",
                                   "--time=" + (ex.time.empty() ? std::to_string(minutes) : ex.time)};
  if (!ex.partition.empty()) argv.push_back("--partition=" + ex.partition);
  argv.insert(argv.end(), ex.sbatch_args.begin(), ex.sbatch_args.end());
  argv.push_back(script);
  std::string out;
  if (Capture(argv, &out) != 0) {
    outcome->error = "sbatch refused the array job: " + Trim(out);
    for (const auto& v : spec.variants) (*states)[v.id] = "CANCELLED: sbatch refused the job";
    return;
  }
  // --parsable: "JOBID" or "JOBID;CLUSTER"
  std::string job = Trim(out);
  job = job.substr(job.find_last_of('\n') == std::string::npos ? 0 : job.find_last_of('\n') + 1);
  job = job.substr(0, job.find(';'));
  outcome->slurm_job = job;
  if (ex.progress)
    std::fprintf(stderr, "ohrp_sweep: %zu variants of %s submitted as Slurm array job %s (time limit %g s "
                         "each, --time %s) -> %s\n", n, spec.scenario_file.c_str(), job.c_str(), spec.time_limit,
                 (ex.time.empty() ? std::to_string(minutes) : ex.time).c_str(), out_dir.c_str());

  // poll until no task is pending or running; on SIGINT/SIGTERM cancel the job and wait for it
  int reported = 0;
  bool cancelled = false;
  const auto poll = std::chrono::milliseconds(static_cast<int>(ex.poll_interval * 1000));
  double failing_since = -1;  // squeue failing (the controller restarting?): give up after a while
  std::string why;
  for (int active; (active = JobActive(job, &why)) != 0;) {
    if (active < 0) {
      if (failing_since < 0) failing_since = ohrp::MonotonicSeconds();
      if (ohrp::MonotonicSeconds() - failing_since > kSqueueGiveUp) {
        outcome->error = "squeue has failed for " + std::to_string(static_cast<int>(kSqueueGiveUp)) +
                         " s (" + why + "); gathering what job " + job + " wrote so far";
        break;
      }
    } else {
      failing_since = -1;
    }
    if (StopRequested() && !cancelled) {
      cancelled = true;
      std::fprintf(stderr, "ohrp_sweep: interrupted; cancelling Slurm job %s\n", job.c_str());
      Capture({"scancel", job}, &out);
    }
    const int k = CountStatuses(spec, out_dir);
    if (ex.progress && k != reported) {
      std::fprintf(stderr, "ohrp_sweep: [%d/%zu] variants finished (Slurm job %s)\n", k, n, job.c_str());
      reported = k;
    }
    std::this_thread::sleep_for(poll);
  }
  for (const auto& [task, state] : TaskStates(job)) (*states)[task] = state + " (Slurm)";
  outcome->interrupted = cancelled;
}

}  // namespace

SweepOutcome RunSweep(const SweepSpec& spec, const Executor& executor, const std::string& out_dir,
                      const RunContext& ctx) {
  SweepOutcome outcome;
  const std::string dir = fs::absolute(out_dir).lexically_normal().string();
  if (!Prepare(spec, dir, &outcome.error)) return outcome;
  InstallStopHandlers();
  std::map<int, std::string> states;
  const double t0 = ohrp::MonotonicSeconds();
  if (executor.kind == Executor::kSlurm)
    RunSlurm(spec, executor, dir, ctx, &outcome, &states);
  else
    RunLocal(spec, executor, dir, ctx, &outcome, &states);
  outcome.wall_time = ohrp::MonotonicSeconds() - t0;
  outcome.results = Gather(spec, dir, states);
  return outcome;
}

}  // namespace ohrp::sweep
