// bench_rt: wake-up lateness of hw_driver's real-time loop at 1 kHz (the Driver class with an
// in-process stub for the boards and no controller attached: read, publish, check, write,
// absolute-deadline sleep) beside a plain absolute-deadline clock_nanosleep loop, measured in
// the same run, in alternating rounds, on the same thread with the same scheduling policy
// (SCHED_FIFO when permitted, else SCHED_OTHER; printed). A third row, for information and not
// in the ratio, runs the driver loop with a controller attached: a forked SCHED_OTHER process
// answering every cycle with a position hold, as a real controller would.
#include <sched.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "cli/command_line.h"
#include "hw_driver/driver.h"
#include "hw_driver/lateness.h"
#include "hw_driver/program.h"
#include "hw_driver/rt.h"

namespace {

using ohrp::hw::LatenessHistogram;

int64_t NowNs() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

// the baseline: sleep to each absolute deadline, record how late the wake-up was
void PlainLoop(int64_t period_ns, long cycles, LatenessHistogram* h) {
  int64_t slot = NowNs();
  for (long i = 0; i < cycles; ++i) {
    slot += period_ns;
    timespec ts{static_cast<time_t>(slot / 1000000000), static_cast<long>(slot % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
    h->Add(NowNs() - slot);
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

void Row(const char* name, const LatenessHistogram& h, unsigned long misses) {
  std::printf("%-28s %8lu %9.1f %9.1f %9.1f %9.1f %9.1f %8lu\n", name,
              static_cast<unsigned long>(h.count()), h.Percentile(50) * 1e-3,
              h.Percentile(90) * 1e-3, h.Percentile(99) * 1e-3, h.Percentile(99.9) * 1e-3,
              h.max_ns() * 1e-3, misses);
}

}  // namespace

int main(int argc, char** argv) {
  double duration = 5.0, period = 0.001;
  int rounds = 100, priority = 80;
  bool controller_row = true;
  std::string model = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml";
  CLI::App app{"bench_rt: hw_driver loop wake-up lateness vs a plain clock_nanosleep loop"};
  app.add_option("--duration", duration, "[s] measured per loop (split over the rounds)")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--rounds", rounds, "alternating rounds (plain, driver)")
      ->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--period", period, "[s]")->capture_default_str()->check(ohrp::cli::Positive());
  app.add_option("--priority", priority, "SCHED_FIFO priority of both loops; 0: SCHED_OTHER")
      ->capture_default_str()->check(ohrp::cli::InRange(0, 99));
  app.add_option("--model", model, "robot model (joints and sensors of the segment)")
      ->capture_default_str()->check(CLI::ExistingFile);
  bool no_controller = false;
  app.add_flag("--no-controller-row", no_controller, "skip the informative row with a controller");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  controller_row = !no_controller;

  std::string error;
  ohrp::shm::ProducerConfig robot;
  const std::string segment = "bench_rt_" + std::to_string(getpid());
  if (!ohrp::hw::LoadRobotDescription(model, segment, period, &robot, &error)) {
    std::fprintf(stderr, "bench_rt: %s\n", error.c_str());
    return 2;
  }
  // one policy for both loops: set here, on this thread, once
  ohrp::hw::RtSettings rt;
  rt.priority = priority;
  const ohrp::hw::RtReport report = ohrp::hw::SetUpRealTime(rt);
  for (const auto& w : report.warnings) std::fprintf(stderr, "bench_rt: warning: %s\n", w.c_str());

  StubIo io;
  ohrp::hw::IoConfig io_config;
  io_config.joint_names = robot.joint_names;
  io.open(io_config, &error);
  const int64_t period_ns = std::llround(period * 1e9);
  const double chunk = duration / rounds;
  const long chunk_cycles = std::lround(chunk / period);

  LatenessHistogram plain, driver, with_controller;
  unsigned long driver_misses = 0, driver_skipped = 0, ctl_misses = 0, ctl_commands = 0,
                ctl_late = 0;
  // one round of the driver loop; with a controller attached when `controller`
  auto run_driver = [&](bool controller, LatenessHistogram* h, unsigned long* misses) {
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
    ohrp::hw::Driver d(o, robot, &io, producer.get());
    d.Run();
    h->Merge(d.live().lateness);
    *misses += d.live().deadline_misses.load();
    if (controller) {
      ctl_commands += d.live().commands.load();
      ctl_late += d.live().late_commands.load();
    } else {
      driver_skipped += d.live().skipped.load();
    }
    producer.reset();  // the controller's read ends
    if (child > 0) {
      kill(child, SIGTERM);
      waitpid(child, nullptr, 0);
    }
  };
  for (int r = 0; r < rounds; ++r) {
    PlainLoop(period_ns, chunk_cycles, &plain);
    run_driver(false, &driver, &driver_misses);
    if (controller_row) run_driver(true, &with_controller, &ctl_misses);
  }

  std::printf("bench_rt: %g Hz, %.1f s per loop in %d alternating rounds, %s for every loop, "
              "robot '%s' (%zu joints), stub boards in-process\n",
              1.0 / period, duration, rounds, report.Describe().c_str(),
              robot.robot_name.c_str(), robot.joint_names.size());
  std::printf("%-28s %8s %9s %9s %9s %9s %9s %8s\n", "wake-up lateness [us]", "cycles", "p50",
              "p90", "p99", "p99.9", "max", "misses");
  Row("plain clock_nanosleep", plain, 0);
  Row("hw_driver loop", driver, driver_misses);
  if (controller_row) {
    Row("hw_driver loop + controller", with_controller, ctl_misses);
    std::printf("(with controller: %lu commands, %lu late; not in the ratio)\n", ctl_commands,
                ctl_late);
  }
  if (driver_skipped > 0) std::printf("hw_driver loop skipped %lu slots\n", driver_skipped);
  const double p99_driver = driver.Percentile(99) * 1e-3;
  const double p99_plain = plain.Percentile(99) * 1e-3;
  std::printf("ratio: %.2f (%.1f / %.1f)\n", p99_plain > 0 ? p99_driver / p99_plain : 0.0,
              p99_driver, p99_plain);
  return 0;
}
