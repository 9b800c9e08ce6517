// bench_rt: wake-up lateness of hw_driver's real-time loop at 1 kHz (the Driver class with an
// in-process stub for the boards and no controller attached: read, publish, check, write,
// wait for the next cycle) beside a plain absolute-deadline clock_nanosleep loop, measured in
// the same run, in alternating rounds, on the same thread with the same scheduling policy
// (SCHED_FIFO when permitted, else SCHED_OTHER; printed). The driver runs twice per round: with
// --wake sleep (its plain sleep) and with --wake spin-tail (the default: sleep short of the
// deadline by a learned margin, then spin; the margin carries over from round to round as it
// would in one long run). Each row gives the loop's CPU use (CLOCK_THREAD_CPUTIME_ID over the
// wall time of its rounds) and the spin-tail's time spent spinning. A last row, for information
// and not in the ratio, runs the spin-tail driver with a controller attached: a forked
// SCHED_OTHER process answering every cycle with a position hold, as a real controller would.
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "cli/command_line.h"
#include "hw_driver/driver.h"
#include "hw_driver/lateness.h"
#include "hw_driver/program.h"
#include "shm_bridge/realtime.h"
#include "hw_driver/wake.h"
#include "shm_bridge/clock.h"

namespace {

using ohrp::hw::LatenessHistogram;

// the baseline: sleep to each absolute deadline, record how late the wake-up was
void PlainLoop(int64_t period_ns, long cycles, LatenessHistogram* h) {
  int64_t slot = ohrp::MonotonicNs();
  for (long i = 0; i < cycles; ++i) {
    slot += period_ns;
    timespec ts{static_cast<time_t>(slot / 1000000000), static_cast<long>(slot % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    h->Add(ohrp::MonotonicNs() - slot);
  }
}

// boards that answer at once with a constant state
class StubIo final : public ohrp::hw::RobotIo {
 public:
  bool open(const ohrp::hw::IoConfig& c, std::string*) override {
    njoint_ = static_cast<int>(c.joint_names.size());
    return true;
  }
  ohrp::hw::IoResult read(ohrp::hw::IoState* s) noexcept override {
    s->faults = 0;
    for (int j = 0; j < njoint_; ++j) s->q[j] = 0.01 * j;
    return ohrp::hw::IoResult::kOk;
  }
  ohrp::hw::IoResult write(const ohrp::hw::IoCommand&) noexcept override {
    return ohrp::hw::IoResult::kOk;
  }
  void close() noexcept override {}

 private:
  int njoint_ = 0;
};

// a controller in a child process (SCHED_OTHER): attaches, answers every cycle, ends with the
// producer
pid_t SpawnController(const std::string& segment) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  sched_param sp{};
  sched_setscheduler(0, SCHED_OTHER, &sp);
  ohrp::shm::RobotAdaptor a;
  for (int i = 0; i < 1000 && !a.open(segment).ok(); ++i) usleep(1000);
  if (!a.is_open()) _exit(2);
  ohrp::shm::SensorBlock s{};
  ohrp::shm::CommandBlock c{};
  c.njoint = a.header().njoint;
  while (a.read(&s) == ohrp::shm::ReadResult::kOk) {
    for (int j = 0; j < c.njoint; ++j) {
      c.joint[j].mode = ohrp::shm::JointMode::kPosition;
      c.joint[j].q_ref = s.q[j];
      c.joint[j].kp = a.header().default_kp[j];
      c.joint[j].kd = a.header().default_kd[j];
    }
    if (a.write(c) != ohrp::shm::ReadResult::kOk) break;
  }
  _exit(0);
}

// the calling thread's CPU time [ns]
// one loop's figures over all its rounds
struct Loop {
  LatenessHistogram lateness;
  unsigned long misses = 0, skipped = 0, commands = 0, late = 0;
  int64_t wall_ns = 0, cpu_ns = 0, spin_ns = 0;
  int64_t margin_ns = 0;  // the spin-tail's margin at the end of the last round

  // times one round of `run` (wall and this thread's CPU)
  template <typename F>
  void Time(F&& run) {
    const int64_t c0 = ohrp::ThreadCpuNs(), w0 = ohrp::MonotonicNs();
    run();
    wall_ns += ohrp::MonotonicNs() - w0;
    cpu_ns += ohrp::ThreadCpuNs() - c0;
  }
};

void Row(const char* name, const Loop& l) {
  const LatenessHistogram& h = l.lateness;
  const double wall = l.wall_ns > 0 ? static_cast<double>(l.wall_ns) : 1.0;
  std::printf("%-30s %7lu %8.1f %8.1f %8.1f %8.1f %8.1f %7lu %7.1f %7.1f\n", name,
              static_cast<unsigned long>(h.count()), h.Percentile(50) * 1e-3,
              h.Percentile(90) * 1e-3, h.Percentile(99) * 1e-3, h.Percentile(99.9) * 1e-3,
              h.max_ns() * 1e-3, l.misses, 100.0 * static_cast<double>(l.cpu_ns) / wall,
              100.0 * static_cast<double>(l.spin_ns) / wall);
}

}  // namespace

int main(int argc, char** argv) {
  double duration = 5.0, period = 0.001;
  int rounds = 100, priority = 80;
  std::string model = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml";
  CLI::App app{"bench_rt: hw_driver loop wake-up lateness, --wake sleep and spin-tail, vs a plain\n"
               "clock_nanosleep loop, in the same run; ends with 'ratio: X.XX (spin-tail p99 us /\n"
               "plain p99 us)'"};
  // every number within its plausible range (cli/plausible.h), checked before anything runs
  app.add_option("--duration", duration, "[s] measured per loop (split over the rounds)")
      ->capture_default_str()->check(ohrp::cli::Plausible("duration"));
  app.add_option("--rounds", rounds, "alternating rounds (plain, driver sleep, driver spin-tail)")
      ->capture_default_str()->check(ohrp::cli::Plausible("repeats"));
  app.add_option("--period", period, "[s]")->capture_default_str()
      ->check(ohrp::cli::Plausible("control_period"));
  app.add_option("--priority", priority, "SCHED_FIFO priority of every loop; 0: SCHED_OTHER")
      ->capture_default_str()->check(ohrp::cli::Plausible("priority"));
  app.add_option("--model", model, "robot model (joints and sensors of the segment)")
      ->capture_default_str()->check(CLI::ExistingFile);
  bool no_controller = false;
  app.add_flag("--no-controller-row", no_controller, "skip the informative row with a controller");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  const bool controller_row = !no_controller;
  // each round runs a whole number of cycles: a plausible count (so a long) before it is one
  const double round_cycles = std::round(duration / rounds / period);
  if (const std::string e = ohrp::cli::CheckPlausible(
          "cycles", round_cycles, "the cycles of a round (--duration / --rounds / --period)");
      !e.empty()) {
    std::fprintf(stderr, "bench_rt: %s\n", e.c_str());
    return 2;
  }

  std::string error;
  ohrp::shm::ProducerConfig robot;
  const std::string segment = "bench_rt_" + std::to_string(getpid());
  if (!ohrp::hw::LoadRobotDescription(model, segment, period, &robot, &error)) {
    std::fprintf(stderr, "bench_rt: %s\n", error.c_str());
    return 2;
  }
  // one policy for every loop: set here, on this thread, once
  ohrp::rt::RtSettings rt;
  rt.priority = priority;
  const ohrp::rt::RtReport report = ohrp::rt::SetUpRealTime(rt);
  for (const auto& w : report.warnings) std::fprintf(stderr, "bench_rt: warning: %s\n", w.c_str());

  StubIo io;
  ohrp::hw::IoConfig io_config;
  io_config.joint_names = robot.joint_names;
  io.open(io_config, &error);
  const int64_t period_ns = std::llround(period * 1e9);
  const double chunk = duration / rounds;
  const long chunk_cycles = static_cast<long>(round_cycles);

  Loop plain, sleep, spin, with_controller;
  // one round of the driver loop in `mode`; with a controller attached when `controller`
  auto run_driver = [&](ohrp::hw::WakeMode mode, bool controller, Loop* loop) {
    ohrp::shm::Status status;
    auto producer = ohrp::shm::Producer::Create(robot, &status);
    if (!producer) {
      std::fprintf(stderr, "bench_rt: %s\n", status.message.c_str());
      std::exit(2);
    }
    pid_t child = -1;
    if (controller) {
      child = SpawnController(segment);
      for (int i = 0; i < 2000 && producer->controller_pid() == 0; ++i) usleep(1000);
    }
    ohrp::hw::DriverOptions o;
    o.period = period;
    o.duration = chunk;
    o.servo_off_time = 0;
    o.watchdog_cycles = 1000000;  // a slow controller here is measured, not a fault
    o.rt.priority = report.fifo ? priority : 0;  // already applied: the same policy
    o.rt.lock_memory = false;
    o.rt.stack_prefault_kb = 0;
    o.wake.mode = mode;
    // the margin learned so far, as one long run would have it
    if (loop->margin_ns > 0) o.wake.initial_margin = static_cast<double>(loop->margin_ns) * 1e-9;
    ohrp::hw::Driver d(o, robot, &io, producer.get());
    loop->Time([&] { d.Run(); });
    loop->lateness.Merge(d.live().lateness);
    loop->misses += d.live().deadline_misses.load();
    loop->skipped += d.live().skipped.load();
    loop->commands += d.live().commands.load();
    loop->late += d.live().late_commands.load();
    loop->spin_ns += d.live().spin_ns.load();
    loop->margin_ns = d.live().wake_margin_ns.load();
    producer.reset();  // the controller's read ends
    if (child > 0) {
      kill(child, SIGTERM);
      waitpid(child, nullptr, 0);
    }
  };
  for (int r = 0; r < rounds; ++r) {
    plain.Time([&] { PlainLoop(period_ns, chunk_cycles, &plain.lateness); });
    run_driver(ohrp::hw::WakeMode::kSleep, false, &sleep);
    run_driver(ohrp::hw::WakeMode::kSpinTail, false, &spin);
    if (controller_row) run_driver(ohrp::hw::WakeMode::kSpinTail, true, &with_controller);
  }

  std::printf("bench_rt: %g Hz, %.1f s per loop in %d alternating rounds, %s for every loop, "
              "robot '%s' (%zu joints), stub boards in-process\n",
              1.0 / period, duration, rounds, report.Describe().c_str(),
              robot.robot_name.c_str(), robot.joint_names.size());
  std::printf("%-30s %7s %8s %8s %8s %8s %8s %7s %7s %7s\n", "wake-up lateness [us]", "cycles",
              "p50", "p90", "p99", "p99.9", "max", "misses", "cpu %", "spin %");
  Row("plain clock_nanosleep", plain);
  Row("hw_driver --wake sleep", sleep);
  Row("hw_driver --wake spin-tail", spin);
  if (controller_row) {
    Row("spin-tail + controller", with_controller);
    std::printf("(with controller: %lu commands, %lu late; not in the ratio)\n",
                with_controller.commands, with_controller.late);
  }
  for (const Loop* l : {&sleep, &spin}) {
    if (l->skipped > 0) {
      std::printf("hw_driver --wake %s skipped %lu slots\n", l == &sleep ? "sleep" : "spin-tail",
                  l->skipped);
    }
  }
  // the cost of the spin-tail: its CPU use above the plain sleep's, and its margin
  const double spin_cpu = spin.wall_ns > 0 ? static_cast<double>(spin.cpu_ns) / spin.wall_ns : 0;
  const double sleep_cpu =
      sleep.wall_ns > 0 ? static_cast<double>(sleep.cpu_ns) / sleep.wall_ns : 0;
  std::printf("spin-tail cost: %.1f %% of the period spinning (%.1f us a cycle), CPU %.1f %% "
              "against %.1f %% for --wake sleep (thread CPU time over wall time); margin at the "
              "end %.1f us\n",
              100.0 * static_cast<double>(spin.spin_ns) / std::max<int64_t>(1, spin.wall_ns),
              static_cast<double>(spin.spin_ns) * 1e-3 /
                  std::max<double>(1.0, static_cast<double>(spin.lateness.count())),
              100.0 * spin_cpu, 100.0 * sleep_cpu, spin.margin_ns * 1e-3);
  const double p99_spin = spin.lateness.Percentile(99) * 1e-3;
  const double p99_plain = plain.lateness.Percentile(99) * 1e-3;
  std::printf("ratio: %.2f (%.2f / %.2f)\n", p99_plain > 0 ? p99_spin / p99_plain : 0.0, p99_spin,
              p99_plain);
  return 0;
}
