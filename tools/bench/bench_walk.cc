// bench_walk: the cost of one `walk` control cycle while walking (pattern generator: preview
// control and the swing feet; the estimate into the plan frame; the stabilizer; WalkIk of the
// legs and the base, and the plan's own IK for the velocity references: controllers/walk.h),
// beside the control period itself (issue 10). The controller runs closed-loop on an in-process
// HRP-1S (sim_host's stepping, soft soles, 1 ms physics, 5 ms control by default) and only its
// update() calls are timed (cycle_timing.h), from its first step's landing to the end of the
// walk; the cycles of standing before the walk are timed too, for comparison. A fingerprint of
// all the commands walk sent tells whether a change to the libraries changed its results.
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>

#include "cli/command_line.h"
#include "controllers/walk.h"
#include "cycle_timing.h"
#include "sim_host/in_process.h"

namespace bench = ohrp::bench;

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  std::string command = "goal 4 0 0";
  double period = 0.005;
  CLI::App app{
      "bench_walk: one control cycle of `walk` while walking (pattern generator + stabilizer +\n"
      "leg IK) on an in-process HRP-1S (soft soles, 1 ms physics), beside the control period;\n"
      "only update() is timed, from the first step's landing to the walk's end. Prints median,\n"
      "p90 and p99 and the ratio cost / period (targets: median under 100 us, p99 under 300 us)."};
  app.add_option("--scene", scene, "MJCF scene with the halfsit keyframe")->capture_default_str();
  app.add_option("--command", command, "the walk command (walk --help)")->capture_default_str();
  app.add_option("--control-period", period, "[s] control period, a multiple of 1 ms")
      ->capture_default_str()->check(ohrp::cli::Plausible("control_period"))
      ->check(ohrp::cli::InRange(0.001, 0.02));
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);
  // what stopped the benchmark, exit code 2
  auto fail = [](const std::string& what) {
    std::fprintf(stderr, "bench_walk: %s\n", what.c_str());
    return 2;
  };

  // the controller and the robot
  ohrp::controllers::WalkOptions o;
  o.balance.ramp = 0.5;
  ohrp::controllers::WalkCommand c;
  std::string error;
  if (!ohrp::controllers::ParseWalkCommand(command, &c, &error)) return fail("--command " + error);
  o.commands.push_back(c);
  ohrp::controllers::ConfigStatus status;
  auto walk = ohrp::controllers::WalkController::Create(o, &status);
  if (!walk) return fail(status.message);
  ohrp::sim::InProcessOptions io;
  io.scene = scene;
  io.keyframe = "halfsit";
  io.control_period = period;
  auto robot = ohrp::sim::InProcessRobot::Create(io, &error);
  if (!robot) return fail(error);
  status = walk->configure(robot->header());
  if (!status.ok()) return fail(status.message);
  walk->activate(robot->sensors());

  // the loop: standing, walking (timed from the first landing), until done or 120 s
  bench::CycleTimes standing, walking;
  ohrp::shm::CommandBlock commands{};
  uint64_t fingerprint = 1469598103934665603ull;
  const int nj = robot->header().njoint;
  bool was_walking = false;
  int cycles = 0;
  while (robot->sensors().time < 120.0 && !(was_walking && walk->done())) {
    auto update = [&] { walk->update(robot->sensors(), &commands); };
    if (!was_walking && walk->standing())
      standing.Time(update);
    else if (was_walking && walk->walking() && walk->walk_stats().steps_done >= 1)
      walking.Time(update);
    else
      update();
    was_walking = was_walking || walk->walking();
    bench::Fingerprint(commands, nj, &fingerprint);
    robot->Cycle(commands);
    ++cycles;
  }
  if (!walk->done()) return fail("the walk did not end on both feet within 120 s");
  if (walking.wall.size() < 100) return fail("fewer than 100 walking cycles timed");

  // the table, the walk's figures, the ratio to the control period
  const double overhead = bench::ThreadCpuOverhead();
  const double median = bench::Quantile(walking.wall, 0.5),
               p99 = bench::Quantile(walking.wall, 0.99);
  std::printf("%-44s %26s   %26s\n", "one control cycle (update only) [us]",
              "wall: median  p90  p99", "thread CPU: median  p90  p99");
  bench::PrintRow("walk standing (balance's stance)", standing, overhead);
  bench::PrintRow("walk walking (generator + stabilizer + IK)", walking, overhead);
  std::printf("(%zu standing and %zu walking cycles; thread CPU clock read cost %.2f us "
              "subtracted)\n", standing.wall.size(), walking.wall.size(), overhead * 1e6);
  std::ostringstream report;
  walk->report(report);
  std::printf("%s", report.str().c_str());
  std::printf("walk: '%s', %d steps, control period %.1f ms; commands fingerprint %016llx over "
              "all %d cycles\n", command.c_str(), walk->walk_stats().steps_done, period * 1e3,
              static_cast<unsigned long long>(fingerprint), cycles);
  std::printf("target: median under 100 us: %s; p99 under 300 us: %s\n",
              median < 100e-6 ? "met" : "NOT met", p99 < 300e-6 ? "met" : "NOT met");
  std::printf("ratio: %.2f (%.2f us / %.2f us)\n", median / period, median * 1e6, period * 1e6);
  return 0;
}
