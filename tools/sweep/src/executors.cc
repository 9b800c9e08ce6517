// The executors (see sweep.h): local worker threads, or a Slurm array job polled until it ends;
// both prepare the same folder and gather it with the same code.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
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

void RunLocal(const SweepSpec& spec, const std::vector<int>& ids, const Executor& ex,
              const std::string& out_dir, const RunContext& ctx, SweepOutcome* outcome,
              std::map<int, std::string>* states) {
  const size_t n = ids.size();
  if (n == 0) return;
  // each variant is a lock-stepped pair (sim_host and its controller): cpus_per_variant CPUs
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  unsigned jobs = ex.jobs > 0 ? static_cast<unsigned>(ex.jobs)
                              : std::max(1u, cores / static_cast<unsigned>(std::max(1, ex.cpus_per_variant)));
  jobs = std::min<unsigned>(jobs, static_cast<unsigned>(n));
  if (ex.progress)
    std::fprintf(stderr, "ohrp_sweep: %zu variants of %s, %u at a time (%d CPUs each, %u cores here), time limit %g s each -> %s\n",
                 n, spec.scenario_file.c_str(), jobs, ex.cpus_per_variant, cores, spec.time_limit, out_dir.c_str());
  std::atomic<size_t> next{0};
  std::atomic<int> done{0};
  std::mutex mutex;
  const std::string tag = std::to_string(getpid());
  auto work = [&] {
    for (size_t i; (i = next++) < n;) {
      const Variant& v = spec.variants[ids[i]];
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

// runs a program with its arguments (no shell: nothing given reaches one) and captures its
// stdout and stderr; its exit code, 127 when it cannot run, 128 + a signal
int Capture(const std::vector<std::string>& argv, std::string* out) {
  out->clear();
  std::vector<char*> args;
  std::vector<std::string> copy = argv;  // made before the fork: the child allocates nothing
  for (auto& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) return -1;
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return -1;
  }
  if (pid == 0) {
    dup2(fds[1], 1);  // dup2 clears O_CLOEXEC on the copies
    dup2(fds[1], 2);
    execvp(args[0], args.data());
    _exit(127);
  }
  ::close(fds[1]);
  char b[4096];
  for (ssize_t k; (k = ::read(fds[0], b, sizeof(b))) != 0;) {
    if (k < 0) {
      if (errno == EINTR) continue;
      break;
    }
    out->append(b, static_cast<size_t>(k));
  }
  ::close(fds[0]);
  int st = 0;
  while (waitpid(pid, &st, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
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

// Slurm's MaxArraySize (scontrol show config); Slurm's default, 1001, when it cannot be asked
int SiteMaxArraySize(bool progress) {
  std::string out;
  int m = 0;
  if (Capture({"scontrol", "show", "config"}, &out) == 0) m = ParseMaxArraySize(out);
  if (m <= 0) {
    m = 1001;
    if (progress)
      std::fprintf(stderr, "ohrp_sweep: scontrol show config gave no MaxArraySize; assuming Slurm's "
                           "default, 1001\n");
  }
  return m;
}

// the array jobs a sweep folder's submissions recorded (slurm/jobs.json), in order
struct ArrayJob {
  std::string job;
  int offset = 0;
  std::string indices;
};
std::string JobsFile(const std::string& out_dir) { return out_dir + "/slurm/jobs.json"; }

std::vector<ArrayJob> ReadJobs(const std::string& out_dir) {
  std::vector<ArrayJob> jobs;
  std::ifstream in(JobsFile(out_dir));
  if (!in) return jobs;
  try {
    nlohmann::json j;
    in >> j;
    for (const auto& x : j)
      jobs.push_back({x.at("job").get<std::string>(), x.at("offset").get<int>(), x.value("indices", std::string())});
  } catch (const std::exception&) {
  }
  return jobs;
}

void RecordJob(const std::string& out_dir, const ArrayJob& a) {
  nlohmann::json j = nlohmann::json::array();
  for (const ArrayJob& x : ReadJobs(out_dir)) j.push_back({{"job", x.job}, {"offset", x.offset}, {"indices", x.indices}});
  j.push_back({{"job", a.job}, {"offset", a.offset}, {"indices", a.indices}});
  std::ofstream(JobsFile(out_dir) + ".tmp") << j.dump(2) << "\n";
  fs::rename(JobsFile(out_dir) + ".tmp", JobsFile(out_dir));
}

// Polls until none of `jobs` has a task pending or running. On SIGINT/SIGTERM: `cancel` cancels
// them (scancel) and waits for their end, else the wait stops there. True when interrupted.
bool PollJobs(const SweepSpec& spec, const Executor& ex, const std::string& out_dir,
              const std::vector<ArrayJob>& jobs, bool cancel, SweepOutcome* outcome) {
  const size_t n = spec.variants.size();
  int reported = -1;
  bool interrupted = false;
  const auto poll = std::chrono::milliseconds(static_cast<int>(ex.poll_interval * 1000));
  double failing_since = -1;  // squeue failing (the controller restarting?): give up after a while
  std::string why, out, names;
  for (const ArrayJob& a : jobs) names += (names.empty() ? "" : ",") + a.job;
  while (true) {
    int active = 0;
    bool failing = false;
    for (const ArrayJob& a : jobs) {
      const int k = JobActive(a.job, &why);
      if (k < 0) failing = true;
      if (k != 0) ++active;
    }
    if (active == 0) break;
    if (failing) {
      if (failing_since < 0) failing_since = ohrp::MonotonicSeconds();
      if (ohrp::MonotonicSeconds() - failing_since > kSqueueGiveUp) {
        outcome->error = "squeue has failed for " + std::to_string(static_cast<int>(kSqueueGiveUp)) +
                         " s (" + why + "); gathering what job(s) " + names + " wrote so far";
        break;
      }
    } else {
      failing_since = -1;
    }
    if (StopRequested() && !interrupted) {
      interrupted = true;
      if (!cancel) {
        std::fprintf(stderr, "ohrp_sweep: interrupted; Slurm job(s) %s go on, gathering what is there\n",
                     names.c_str());
        break;
      }
      std::fprintf(stderr, "ohrp_sweep: interrupted; cancelling Slurm job(s) %s\n", names.c_str());
      for (const ArrayJob& a : jobs) Capture({"scancel", a.job}, &out);
    }
    const int k = CountStatuses(spec, out_dir);
    if (ex.progress && k != reported) {
      std::fprintf(stderr, "ohrp_sweep: [%d/%zu] variants finished (Slurm job(s) %s)\n", k, n, names.c_str());
      reported = k;
    }
    std::this_thread::sleep_for(poll);
  }
  return interrupted;
}

// what Slurm says of each job's tasks, by variant id (later jobs over earlier ones)
void CollectStates(const std::vector<ArrayJob>& jobs, std::map<int, std::string>* states) {
  for (const ArrayJob& a : jobs)
    for (const auto& [task, state] : TaskStates(a.job)) (*states)[a.offset + task] = state + " (Slurm)";
}

void RunSlurm(const SweepSpec& spec, const std::vector<int>& ids, const Executor& ex,
              const std::string& out_dir, const RunContext& ctx, SweepOutcome* outcome,
              std::map<int, std::string>* states) {
  if (ids.empty()) return;
  // the task script: ohrp_sweep --task on this folder (a shared filesystem on a real cluster),
  // its chunk's offset as the script's argument
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
                 "#!/bin/sh\n# one variant of sweep %s: variants/v<$1 + SLURM_ARRAY_TASK_ID> (ohrp_sweep --task)\n"
                 "exec %s --task %s --task-offset \"${1:-0}\"%s\n",
                 spec.name.c_str(), Quote(ctx.bin_dir + "/ohrp_sweep").c_str(), Quote(out_dir).c_str(),
                 ctx.run_plots ? " --run-plots" : "");
    if (std::fclose(f) != 0) {
      outcome->error = "cannot write " + script;
      return;
    }
    fs::permissions(script, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                fs::perms::others_read | fs::perms::others_exec);
  }
  // arrays no larger than the site allows: one job per chunk of MaxArraySize variants
  const std::vector<ArrayChunk> chunks = ChunkArray(ids, SiteMaxArraySize(ex.progress));
  const int minutes = static_cast<int>(std::ceil((spec.time_limit + 60) / 60));
  const std::string time = ex.time.empty() ? std::to_string(minutes) : ex.time;
  bool cpus_given = false;  // --sbatch-arg=--cpus-per-task=N wins over cpus_per_variant
  for (const auto& a : ex.sbatch_args) cpus_given = cpus_given || a.rfind("--cpus-per-task", 0) == 0 || a == "-c";
  std::vector<ArrayJob> jobs;
  for (const ArrayChunk& c : chunks) {
    std::string array = "--array=" + c.indices;
    if (ex.max_running > 0) array += "%" + std::to_string(ex.max_running);
    const std::string output = slurm_dir + (c.offset == 0 ? "/task_%a.out" : "/chunk" + std::to_string(c.offset) + "_task_%a.out");
    std::vector<std::string> argv = {"sbatch", "--parsable", array, "--job-name=ohrp-sweep-" + spec.name,
                                     "--output=" + output, "--chdir=" + ctx.source_dir,
                                     "--ntasks=1", "--time=" + time};
    if (!cpus_given) argv.push_back("--cpus-per-task=" + std::to_string(ex.cpus_per_variant));
    if (!ex.partition.empty()) argv.push_back("--partition=" + ex.partition);
    argv.insert(argv.end(), ex.sbatch_args.begin(), ex.sbatch_args.end());
    argv.push_back(script);
    argv.push_back(std::to_string(c.offset));
    std::string out;
    if (Capture(argv, &out) != 0) {
      outcome->error = "sbatch refused the array job" +
                       (chunks.size() > 1 ? " of variants " + std::to_string(c.offset) + "+[" + c.indices + "]" : std::string()) +
                       ": " + Trim(out);
      // this chunk and the later ones never run; those submitted are polled and gathered below
      for (int id : ids)
        if (id >= c.offset) (*states)[id] = "CANCELLED: sbatch refused the job";
      break;
    }
    // --parsable: "JOBID" or "JOBID;CLUSTER"
    std::string job = Trim(out);
    job = job.substr(job.find_last_of('\n') == std::string::npos ? 0 : job.find_last_of('\n') + 1);
    job = job.substr(0, job.find(';'));
    jobs.push_back({job, c.offset, c.indices});
    RecordJob(out_dir, jobs.back());
    if (ex.progress)
      std::fprintf(stderr, "ohrp_sweep: %d variants of %s submitted as Slurm array job %s (variants %d + [%s], "
                           "time limit %g s each, --time %s) -> %s\n", c.count, spec.scenario_file.c_str(),
                   job.c_str(), c.offset, c.indices.c_str(), spec.time_limit, time.c_str(), out_dir.c_str());
  }
  if (!jobs.empty()) outcome->slurm_job = jobs.front().job;
  for (size_t k = 1; k < jobs.size(); ++k) outcome->slurm_job += "," + jobs[k].job;
  outcome->interrupted = PollJobs(spec, ex, out_dir, jobs, true, outcome);
  CollectStates(jobs, states);
}

}  // namespace

SweepOutcome RunVariants(const SweepSpec& spec, const std::vector<int>& ids,
                         const Executor& executor, const std::string& out_dir,
                         const RunContext& ctx) {
  SweepOutcome outcome;
  const std::string dir = fs::absolute(out_dir).lexically_normal().string();
  InstallStopHandlers();
  std::map<int, std::string> states;
  const double t0 = ohrp::MonotonicSeconds();
  if (executor.kind == Executor::kSlurm)
    RunSlurm(spec, ids, executor, dir, ctx, &outcome, &states);
  else
    RunLocal(spec, ids, executor, dir, ctx, &outcome, &states);
  outcome.wall_time = ohrp::MonotonicSeconds() - t0;
  outcome.results = Gather(spec, dir, states);
  return outcome;
}

SweepOutcome RunSweep(const SweepSpec& spec, const Executor& executor, const std::string& out_dir,
                      const RunContext& ctx) {
  const std::string dir = fs::absolute(out_dir).lexically_normal().string();
  SweepOutcome outcome;
  if (!Prepare(spec, dir, &outcome.error)) return outcome;
  std::vector<int> ids;
  for (const auto& v : spec.variants) ids.push_back(v.id);
  return RunVariants(spec, ids, executor, dir, ctx);
}

SweepOutcome GatherFolder(const SweepSpec& spec, const std::string& out_dir,
                          const Executor& executor) {
  SweepOutcome outcome;
  const std::string dir = fs::absolute(out_dir).lexically_normal().string();
  InstallStopHandlers();
  const double t0 = ohrp::MonotonicSeconds();
  std::map<int, std::string> states;
  const std::vector<ArrayJob> jobs = ReadJobs(dir);
  if (!jobs.empty()) {
    outcome.interrupted = PollJobs(spec, executor, dir, jobs, false, &outcome);
    CollectStates(jobs, &states);
    outcome.slurm_job = jobs.front().job;
    for (size_t k = 1; k < jobs.size(); ++k) outcome.slurm_job += "," + jobs[k].job;
  }
  outcome.wall_time = ohrp::MonotonicSeconds() - t0;
  outcome.results = Gather(spec, dir, states);
  return outcome;
}

}  // namespace ohrp::sweep
