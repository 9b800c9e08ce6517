// bench_loop: wall time per control cycle of sim_host + posture in lock-step (two processes,
// 1 ms physics, 1 ms control), beside sim_host's own physics step in one process (servo,
// soles, mj_step on the same model) measured in the same run, and the real-time factor of both;
// with the CPU time each process of the pair used per cycle (a waiter of the handshake spins for
// a bounded time before it sleeps: that CPU time shows what the spinning costs). posture runs
// without its self-collision check for the ratio (what the loop costs beyond the physics is the
// handshake and posture's own few microseconds); a second row gives the loop with the check, as
// posture runs by default (docs/selfcollision.md).
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli/command_line.h"
#include "quantile.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/step.h"
#include "shm_bridge/clock.h"

namespace fs = std::filesystem;

namespace {

using ohrp::bench::Median;

// bare loop: sim_host's physics step alone (servo, soft soles, mj_step), in one process;
// returns wall seconds per step
double BareLoop(const std::string& scene_path, double dt, int steps) {
  std::string error;
  auto scene = ohrp::model::Scene::Load(scene_path, &error);
  if (!scene) {
    std::fprintf(stderr, "bench_loop: %s\n", error.c_str());
    std::exit(2);
  }
  scene->m()->opt.timestep = dt;
  scene->Reset("", &error);
  ohrp::model::RobotMap robot;
  if (!ohrp::model::MapRobot(scene->m(), &robot, &error)) {
    std::fprintf(stderr, "bench_loop: %s\n", error.c_str());
    std::exit(2);
  }
  // the feet as sim_host sets them up (soft soles by default), then sim_host's own step
  std::unique_ptr<ohrp::contact::SoftFootContact> soft;
  if (!ohrp::sim::SetUpFeet(scene->m(), ohrp::sim::FeetOptions{}, robot.total_mass, &soft,
                            &error)) {
    std::fprintf(stderr, "bench_loop: %s\n", error.c_str());
    std::exit(2);
  }
  ohrp::model::Servo servo(robot);
  servo.HoldCurrent(scene->d());
  ohrp::sim::PhysicsStep step(scene->m(), scene->d(), {&servo, soft.get()});
  const double t0 = ohrp::MonotonicSeconds();
  for (int i = 0; i < steps; ++i) step.Step();
  return (ohrp::MonotonicSeconds() - t0) / steps;
}

// `v` as an argument, every digit kept (std::to_string rounds 1.25e-5 to "0.000013")
std::string Arg(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", v);
  return buf;
}

pid_t Spawn(const std::vector<std::string>& argv, bool silent) {
  std::vector<char*> a;
  for (auto& s : argv) a.push_back(const_cast<char*>(s.c_str()));
  a.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (silent) {
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 1);
      dup2(null, 2);
    }
    execv(a[0], a.data());
    _exit(127);
  }
  return pid;
}

// waits for `pid`; its exit status in `*status`, its CPU time (user + system) [s] returned
double ReapWithCpu(pid_t pid, int* status) {
  rusage usage{};
  wait4(pid, status, 0, &usage);
  double cpu = 0.0;
  for (const timeval& t : {usage.ru_utime, usage.ru_stime}) {
    cpu += static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  }
  return cpu;
}

// CPU time [s] of each process of the pair over its whole run (set-up included)
struct PairCpu {
  double sim_host = 0.0;
  double controller = 0.0;
};

// sim_host + posture in lock-step (posture's self-collision check on when `self_collision`, an
// ohrp_view observing the segment when `viewer`); returns sim_host's wall seconds per cycle
double TwoProcessLoop(const std::string& bin, const std::string& scene, double dt, double duration,
                      const std::string& summary, PairCpu* cpu, bool self_collision,
                      bool viewer = false) {
  const std::string seg = "bench_loop_" + std::to_string(getpid());
  const pid_t sim = Spawn({bin + "/sim_host", "--scene", scene, "--segment", seg, "--physics-dt",
                           Arg(dt), "--control-period", Arg(dt),
                           "--duration", Arg(duration), "--summary", summary,
                           "--quiet", "--progress", "0"}, false);
  const pid_t view = viewer ? Spawn({bin + "/ohrp_view", seg, "--scene", scene, "--attach-timeout", "20",
                                     "--port", "0"}, true)
                            : -1;
  std::vector<std::string> posture = {bin + "/posture", "--segment", seg, "--attach-timeout", "20"};
  if (!self_collision) posture.push_back("--no-self-collision");
  const pid_t ctl = Spawn(posture, true);
  int st = 0;
  cpu->sim_host = ReapWithCpu(sim, &st);
  const bool sim_ok = WIFEXITED(st) && WEXITSTATUS(st) == 0;
  cpu->controller = ReapWithCpu(ctl, &st);
  if (view > 0) {
    kill(view, SIGTERM);
    waitpid(view, &st, 0);
  }
  if (!sim_ok) {
    std::fprintf(stderr, "bench_loop: sim_host failed; run it by hand to see why\n");
    std::exit(1);
  }
  std::ifstream in(summary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto k = text.find("\"wall_per_cycle\":");
  return k == std::string::npos ? 0 : std::stod(text.substr(k + 17));
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  double dt = 0.001, duration = 3.0;
  int repeats = 7;
  bool viewer = false;
  CLI::App app{
      "bench_loop: wall time per control cycle of sim_host + posture in lock-step (separate\n"
      "processes, physics step = control period) beside sim_host's physics step alone (step.h) on the same\n"
      "model, measured alternately in the same run. Prints medians and the ratio: the median over\n"
      "the rounds of each round's lock-step cycle over its bare step, the bare step measured just\n"
      "before and just after the lock-step run (the machine's speed drifts between rounds on a\n"
      "shared VM). posture runs without its self-collision check for the ratio; a second row has\n"
      "the check on."};
  app.add_option("--scene", scene, "MJCF scene")->capture_default_str();
  // every number within its plausible range (cli/plausible.h), checked before anything runs;
  // --dt is both a physics step and a control period
  app.add_option("--dt", dt, "physics step and control period [s]")->capture_default_str()
      ->check(ohrp::cli::Plausible("physics_dt"))->check(ohrp::cli::Plausible("control_period"));
  app.add_option("--duration", duration, "simulated seconds per measurement")->capture_default_str()
      ->check(ohrp::cli::Plausible("duration"));
  app.add_option("--repeats", repeats, "measurements of each kind")->capture_default_str()
      ->check(ohrp::cli::Plausible("repeats"));
  app.add_flag("--viewer", viewer, "also measure the lock-step with an ohrp_view attached (docs/view.md)");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  // the steps of a measurement, a plausible number (so an int) before it is one
  const double step_count = std::floor(duration / dt);
  if (const std::string e = ohrp::cli::CheckPlausible("steps", step_count, "--duration / --dt");
      !e.empty()) {
    std::fprintf(stderr, "bench_loop: %s\n", e.c_str());
    return 2;
  }
  ohrp::model::InstallMujocoHandlers(nullptr);
  const std::string bin = fs::canonical("/proc/self/exe").parent_path().string();
  const std::string summary = "/tmp/bench_loop_" + std::to_string(getpid()) + ".json";

  std::vector<double> bare, loop, ratios, sim_cpu, ctl_cpu, watched, checked;
  const int steps = static_cast<int>(step_count);
  for (int r = 0; r < repeats; ++r) {
    const double before = BareLoop(scene, dt, steps);
    PairCpu cpu;
    loop.push_back(TwoProcessLoop(bin, scene, dt, duration, summary, &cpu, false));
    bare.push_back(0.5 * (before + BareLoop(scene, dt, steps)));
    ratios.push_back(loop.back() / bare.back());
    sim_cpu.push_back(cpu.sim_host / steps);
    ctl_cpu.push_back(cpu.controller / steps);
    std::fprintf(stderr,
                 "  run %d/%d: bare %.1f us/step, sim_host+posture %.1f us/cycle (cpu: sim_host "
                 "%.1f, posture %.1f us/cycle)\n",
                 r + 1, repeats, bare.back() * 1e6, loop.back() * 1e6, sim_cpu.back() * 1e6,
                 ctl_cpu.back() * 1e6);
    PairCpu checked_cpu;
    checked.push_back(TwoProcessLoop(bin, scene, dt, duration, summary, &checked_cpu, true));
    std::fprintf(stderr, "  run %d/%d: the same with posture's self-collision check %.1f us/cycle\n",
                 r + 1, repeats, checked.back() * 1e6);
    if (viewer) {
      PairCpu watched_cpu;
      watched.push_back(TwoProcessLoop(bin, scene, dt, duration, summary, &watched_cpu, false, true));
      std::fprintf(stderr, "  run %d/%d: sim_host+posture with ohrp_view attached %.1f us/cycle\n",
                   r + 1, repeats, watched.back() * 1e6);
    }
  }
  fs::remove(summary);
  const double b = Median(bare), l = Median(loop);
  std::printf("%-34s %14s %12s\n", "loop", "median [us]", "real time");
  std::printf("%-34s %14.1f %11.1fx\n", "sim_host step alone (1 process)", b * 1e6, dt / b);
  std::printf("%-34s %14.1f %11.1fx\n", "sim_host + posture (lock-step)", l * 1e6, dt / l);
  std::printf("cpu per cycle (whole runs, set-up included): sim_host %.1f us, posture %.1f us\n",
              Median(sim_cpu) * 1e6, Median(ctl_cpu) * 1e6);
  const double c = Median(checked);
  std::printf("%-34s %14.1f %11.1fx  (posture's default; not in the ratio)\n",
              "the same, self-collision check on", c * 1e6, dt / c);
  if (viewer) {
    const double w = Median(watched);
    std::printf("%-34s %14.1f %11.1fx\n", "the same with ohrp_view attached", w * 1e6, dt / w);
  }
  std::printf("ratio = the median of the %d rounds' lock-step cycle / bare step (each round's bare step "
              "measured just before and after its lock-step run); medians in brackets\n", repeats);
  std::printf("ratio: %.2f (%.1f us / %.1f us)\n", Median(ratios), l * 1e6, b * 1e6);
  return 0;
}
