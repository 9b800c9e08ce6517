// bench_bridge: the lock-step round trip through shm_bridge (PublishSensors -> read -> write ->
// WaitCommands) between two processes, against its baseline, a raw ping-pong of two
// process-shared POSIX semaphores, measured in the same run with the same cycle count and
// the same CPU pinning. Times are taken on the producer (pinging) side; the CPU time is that
// of both processes (what a waiter that spins instead of sleeping costs).
//
//   bench_bridge [--cycles N] [--warmup W] [--pin both|split|same|none]
//
// Prints one table per pinning (both: split, then same), each with the rows name, median [us],
// p99 [us], cpu [us/cycle], cycles, and the line
//   ratio: X.XX (<bridge median us> / <raw median us>)
#include <sched.h>
#include <semaphore.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/clock.h"

namespace {

using ohrp::shm::CommandBlock;
using ohrp::shm::ReadResult;
using ohrp::shm::SensorBlock;
using ohrp::shm::WaitResult;

constexpr int kJoints = 30;           // a humanoid-sized joint count
constexpr double kWaitTimeout = 2.0;  // [s] per cycle; a healthy pair answers in microseconds

//---------------- pinning and statistics ----------------

enum class Pin { kSplit, kSame, kNone };

struct Pinning {
  Pin pin = Pin::kSplit;
  int producer_cpu = -1;  // -1: not pinned
  int controller_cpu = -1;
};

Pinning ChoosePinning(Pin pin) {
  Pinning p;
  p.pin = pin;
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  if (pin == Pin::kNone || sched_getaffinity(0, sizeof(allowed), &allowed) != 0) {
    p.pin = Pin::kNone;
    return p;
  }
  std::vector<int> cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &allowed)) cpus.push_back(c);
  }
  if (cpus.empty()) {
    p.pin = Pin::kNone;
    return p;
  }
  if (pin == Pin::kSplit && cpus.size() < 2) p.pin = Pin::kSame;
  p.producer_cpu = cpus[0];
  p.controller_cpu = p.pin == Pin::kSplit ? cpus[1] : cpus[0];
  return p;
}

std::string Describe(const Pinning& p) {
  switch (p.pin) {
    case Pin::kSplit:
      return "split (producer/pinger on cpu " + std::to_string(p.producer_cpu) +
             ", controller/ponger on cpu " + std::to_string(p.controller_cpu) + ")";
    case Pin::kSame:
      return "same (both processes on cpu " + std::to_string(p.producer_cpu) + ")";
    case Pin::kNone:
      return "none (the scheduler places both processes)";
  }
  return "?";
}

void PinTo(int cpu) {
  if (cpu < 0) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  sched_setaffinity(0, sizeof(set), &set);
}

// one measurement: the round trips [us] and the CPU time both processes used [us]
struct Sample {
  std::vector<double> us;
  double cpu_us = 0.0;
  int total_cycles = 0;  // warm-up included, the cycles cpu_us was spent on
};

struct Stats {
  double median = 0.0;  // [us]
  double p99 = 0.0;     // [us]
  double cpu = 0.0;     // CPU time of both processes per cycle [us]
  std::size_t cycles = 0;
};

Stats Summarize(const Sample& sample) {
  std::vector<double> us = sample.us;
  Stats s;
  if (sample.total_cycles > 0) s.cpu = sample.cpu_us / sample.total_cycles;
  s.cycles = us.size();
  if (us.empty()) return s;
  std::sort(us.begin(), us.end());
  s.median = us[us.size() / 2];
  const auto i99 = static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(us.size())));
  s.p99 = us[std::clamp<std::size_t>(i99, 1, us.size()) - 1];
  return s;
}

// waits for a child; true when it exited with code 0. Adds its CPU time [us] to `*cpu_us`.
bool Reap(pid_t pid, double* cpu_us = nullptr) {
  int status = 0;
  rusage usage{};
  if (wait4(pid, &status, 0, &usage) != pid) return false;
  if (cpu_us != nullptr) {
    for (const timeval& t : {usage.ru_utime, usage.ru_stime}) {
      *cpu_us += 1e6 * static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec);
    }
  }
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

//---------------- the bridge round trip ----------------

// the controller process: answers every cycle until the producer stops
int RunController(const std::string& segment, int cpu) {
  PinTo(cpu);
  ohrp::shm::RobotAdaptor adaptor;
  ohrp::shm::Status s;
  for (int attempt = 0; attempt < 2000; ++attempt) {
    s = adaptor.open(segment);
    if (s.code != ohrp::shm::Error::kNoSegment) break;
    usleep(1000);
  }
  if (!s.ok()) {
    std::fprintf(stderr, "bench_bridge: controller: %s\n", s.message.c_str());
    return 2;
  }
  SensorBlock in{};
  CommandBlock out{};
  out.njoint = kJoints;
  for (;;) {
    const ReadResult r = adaptor.read(&in);
    if (r == ReadResult::kProducerStopped) return 0;
    if (r != ReadResult::kOk) return 3;
    for (int j = 0; j < kJoints; ++j) {
      out.joint[j].mode = ohrp::shm::JointMode::kPosition;
      out.joint[j].q_ref = in.q[j];
      out.joint[j].dq_ref = 0.0;
      out.joint[j].kp = 100.0;
      out.joint[j].kd = 1.0;
    }
    if (adaptor.write(out) != ReadResult::kOk) return 4;
  }
}

bool MeasureBridge(int cycles, int warmup, const Pinning& pin, Sample* out) {
  std::vector<double>* us = &out->us;
  ohrp::shm::ProducerConfig config;
  config.segment_name = "bench_bridge_" + std::to_string(getpid());
  config.robot_name = "bench";
  for (int j = 0; j < kJoints; ++j)
    config.joint_names.push_back(std::string("j").append(std::to_string(j)));
  ohrp::shm::Status status;
  auto producer = ohrp::shm::Producer::Create(config, &status);
  if (producer == nullptr) {
    std::fprintf(stderr, "bench_bridge: %s\n", status.message.c_str());
    return false;
  }
  const pid_t child = fork();
  if (child == 0) _exit(RunController(config.segment_name, pin.controller_cpu));
  PinTo(pin.producer_cpu);
  for (int i = 0; i < 5000 && producer->controller_pid() == 0; ++i) usleep(1000);
  if (producer->controller_pid() == 0) {
    std::fprintf(stderr, "bench_bridge: the controller process did not attach\n");
    kill(child, SIGKILL);
    Reap(child);
    return false;
  }

  bool ok = true;
  CommandBlock commands{};
  us->reserve(static_cast<std::size_t>(cycles));
  const double cpu0 = 1e6 * ohrp::ThreadCpuSeconds();
  for (int k = 0; k < warmup + cycles && ok; ++k) {
    const double t0 = 1e6 * ohrp::MonotonicSeconds();
    SensorBlock& s = producer->BeginSensors();
    s.cycle = static_cast<uint64_t>(k);
    s.time = 0.001 * k;
    for (int j = 0; j < kJoints; ++j) {
      s.q[j] = 0.001 * k + j;
      s.dq[j] = 0.0;
    }
    producer->PublishSensors();
    const WaitResult r = producer->WaitCommands(kWaitTimeout, &commands);
    const double t1 = 1e6 * ohrp::MonotonicSeconds();
    ok = r == WaitResult::kCommands && commands.answers_cycle == static_cast<uint64_t>(k);
    if (k >= warmup) us->push_back(t1 - t0);
  }
  out->cpu_us = 1e6 * ohrp::ThreadCpuSeconds() - cpu0;
  out->total_cycles = warmup + cycles;
  if (!ok) std::fprintf(stderr, "bench_bridge: the bridge round trip failed\n");
  producer.reset();  // the controller's next read returns kProducerStopped
  return Reap(child, &out->cpu_us) && ok;
}

//---------------- the raw semaphore baseline ----------------

struct RawPair {
  sem_t ping;
  sem_t pong;
};

bool MeasureRaw(int cycles, int warmup, const Pinning& pin, Sample* out) {
  std::vector<double>* us = &out->us;
  void* mem =
      mmap(nullptr, sizeof(RawPair), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (mem == MAP_FAILED) return false;
  auto* pair = static_cast<RawPair*>(mem);
  sem_init(&pair->ping, 1, 0);
  sem_init(&pair->pong, 1, 0);
  const int total = warmup + cycles;
  const pid_t child = fork();
  if (child == 0) {
    PinTo(pin.controller_cpu);
    for (int k = 0; k < total; ++k) {
      while (sem_wait(&pair->ping) != 0) {
      }
      sem_post(&pair->pong);
    }
    _exit(0);
  }
  PinTo(pin.producer_cpu);
  us->reserve(static_cast<std::size_t>(cycles));
  const double cpu0 = 1e6 * ohrp::ThreadCpuSeconds();
  for (int k = 0; k < total; ++k) {
    const double t0 = 1e6 * ohrp::MonotonicSeconds();
    sem_post(&pair->ping);
    while (sem_wait(&pair->pong) != 0) {
    }
    const double t1 = 1e6 * ohrp::MonotonicSeconds();
    if (k >= warmup) us->push_back(t1 - t0);
  }
  out->cpu_us = 1e6 * ohrp::ThreadCpuSeconds() - cpu0;
  out->total_cycles = total;
  const bool ok = Reap(child, &out->cpu_us);
  sem_destroy(&pair->ping);
  sem_destroy(&pair->pong);
  munmap(mem, sizeof(RawPair));
  return ok;
}

// measures both pairs with one pinning and prints their table; false when one failed
bool RunTable(Pin pin, int cycles, int warmup) {
  const Pinning pinning = ChoosePinning(pin);
  std::printf("pinning: %s, same for both pairs\n", Describe(pinning).c_str());
  std::fflush(stdout);  // the children inherit stdio buffers

  // each measurement runs in its own forked pair; the parent stays unpinned in between
  Sample raw_sample, bridge_sample;
  cpu_set_t original;
  sched_getaffinity(0, sizeof(original), &original);
  const bool raw_ok = MeasureRaw(cycles, warmup, pinning, &raw_sample);
  sched_setaffinity(0, sizeof(original), &original);
  const bool bridge_ok = MeasureBridge(cycles, warmup, pinning, &bridge_sample);
  sched_setaffinity(0, sizeof(original), &original);
  if (!raw_ok || !bridge_ok) {
    std::fprintf(stderr, "bench_bridge: a measurement failed (raw %s, bridge %s)\n",
                 raw_ok ? "ok" : "failed", bridge_ok ? "ok" : "failed");
    return false;
  }

  const Stats bridge = Summarize(bridge_sample);
  const Stats raw = Summarize(raw_sample);
  std::printf("%-28s %12s %12s %17s %10s\n", "name", "median [us]", "p99 [us]",
              "cpu [us/cycle]", "cycles");
  std::printf("%-28s %12.2f %12.2f %17.2f %10zu\n", "bridge (shm_bridge)", bridge.median,
              bridge.p99, bridge.cpu, bridge.cycles);
  std::printf("%-28s %12.2f %12.2f %17.2f %10zu\n", "raw (POSIX sem ping-pong)", raw.median,
              raw.p99, raw.cpu, raw.cycles);
  std::printf("ratio: %.2f (%.2f / %.2f)\n\n", bridge.median / raw.median, bridge.median,
              raw.median);
  std::fflush(stdout);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench_bridge: shm_bridge lock-step round trip vs a raw POSIX semaphore ping-pong"};
  int cycles = 20000;
  int warmup = 1000;
  std::string pin_name = "both";
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  // (each measured cycle's time is kept: --cycles is a number of samples too)
  app.add_option("--cycles", cycles, "measured cycles per pair")->check(ohrp::cli::Plausible("cycles"))
      ->check(ohrp::cli::Plausible("samples"));
  app.add_option("--warmup", warmup, "unmeasured cycles before each measurement")
      ->check(ohrp::cli::Plausible("count"));
  app.add_option("--pin", pin_name,
                 "CPU pinning, the same for both pairs: split (pinger and ponger on two CPUs), "
                 "same (both on one CPU), none, or both (a split table, then a same table)")
      ->check(CLI::IsMember({"both", "split", "same", "none"}))
      ->capture_default_str();
  app.footer(
      "cpu [us/cycle] is the CPU time both processes used per round trip (warm-up included): a\n"
      "waiter that spins uses its CPU while it spins (the bridge spins for a bounded, adaptive\n"
      "time when its peer runs on another CPU, and yields its CPU when both share one;\n"
      "docs/architecture.md).");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  std::printf("bench_bridge: lock-step round trip per cycle, timed on the producer side\n");
  std::printf("cycles: %d measured after %d warm-up, %d joints\n\n", cycles, warmup, kJoints);
  std::vector<Pin> pins;
  if (pin_name == "both") pins = {Pin::kSplit, Pin::kSame};
  if (pin_name == "split") pins = {Pin::kSplit};
  if (pin_name == "same") pins = {Pin::kSame};
  if (pin_name == "none") pins = {Pin::kNone};
  for (Pin pin : pins) {
    if (!RunTable(pin, cycles, warmup)) return 1;
  }
  return 0;
}
