// bench_walk: the cost of one `walk` control cycle while walking (pattern generator: preview
// control and the swing feet; the estimate into the plan frame; the stabilizer; WalkIk of the
// legs and the base, and the plan's own IK for the velocity references: controllers/walk.h),
// beside the control period itself (issue 10). The controller runs closed-loop on an in-process
// HRP-1S (sim_host's stepping, soft soles, 1 ms physics, 5 ms control by default) and only its
// update() calls are timed (cycle_timing.h), from its first step's landing to the end of the
// walk; the cycles of standing before the walk are timed too, for comparison. A fingerprint of
// all the commands walk sent tells whether a change to the libraries changed its results.
// Issue 31: the same walk on a second robot through its profile (--beside, Unitree G1 by default:
// its profile's stance, servo and step limits), its rows printed beside HRP-1S's.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include "cli/command_line.h"
#include "controllers/walk.h"
#include "cycle_timing.h"
#include "robot_model/profile.h"
#include "sim_host/in_process.h"

namespace bench = ohrp::bench;

namespace {

// the robot a walk is timed on
struct Robot {
  std::string label;    // the rows' name
  std::string scene;    // what the in-process simulator runs
  std::string keyframe; // the scene's start
  std::string model;    // walk's --model ("": HRP-1S's default)
  std::string stance;   // walk's --stance-keyframe ("": HRP-1S's pose file)
};

struct Timed {
  bench::CycleTimes standing, walking;
  uint64_t fingerprint = 1469598103934665603ull;
  int cycles = 0, steps = 0;
  std::string report;
};

// walks `command` on `r` in-process, timing update(); "" or what stopped it
std::string TimeWalk(const Robot& r, const std::string& command, double period, Timed* out) {
  ohrp::controllers::WalkOptions o;
  o.balance.ramp = 0.5;
  o.balance.model = r.model;
  o.balance.keyframe = r.stance;
  ohrp::controllers::WalkCommand c;
  std::string error;
  if (!ohrp::controllers::ParseWalkCommand(command, &c, &error)) return "--command " + error;
  o.commands.push_back(c);
  ohrp::controllers::ConfigStatus status;
  auto walk = ohrp::controllers::WalkController::Create(o, &status);
  if (!walk) return r.label + ": " + status.message;
  ohrp::sim::InProcessOptions io;
  io.scene = r.scene;
  io.keyframe = r.keyframe;
  io.control_period = period;
  auto robot = ohrp::sim::InProcessRobot::Create(io, &error);
  if (!robot) return r.label + ": " + error;
  status = walk->configure(robot->header());
  if (!status.ok()) return r.label + ": " + status.message;
  walk->activate(robot->sensors());

  // the loop: standing, walking (timed from the first landing), until done or 120 s
  ohrp::shm::CommandBlock commands{};
  const int nj = robot->header().njoint;
  bool was_walking = false;
  while (robot->sensors().time < 120.0 && !(was_walking && walk->done())) {
    auto update = [&] { walk->update(robot->sensors(), &commands); };
    if (!was_walking && walk->standing())
      out->standing.Time(update);
    else if (was_walking && walk->walking() && walk->walk_stats().steps_done >= 1)
      out->walking.Time(update);
    else
      update();
    was_walking = was_walking || walk->walking();
    bench::Fingerprint(commands, nj, &out->fingerprint);
    robot->Cycle(commands);
    ++out->cycles;
  }
  if (!walk->done()) return r.label + ": the walk did not end on both feet within 120 s";
  if (out->walking.wall.size() < 100) return r.label + ": fewer than 100 walking cycles timed";
  out->steps = walk->walk_stats().steps_done;
  std::ostringstream report;
  walk->report(report);
  out->report = report.str();
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  std::string command = "goal 4 0 0";
  std::string beside = std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml";
  double period = 0.005;
  CLI::App app{
      "bench_walk: one control cycle of `walk` while walking (pattern generator + stabilizer +\n"
      "leg IK) on an in-process HRP-1S (soft soles, 1 ms physics), beside the control period;\n"
      "only update() is timed, from the first step's landing to the walk's end. Prints median,\n"
      "p90 and p99 and the ratio cost / period (targets: median under 100 us, p99 under 300 us).\n"
      "The same walk on a second robot through its profile (--beside) is printed beside it."};
  app.add_option("--scene", scene, "MJCF scene with the halfsit keyframe")->capture_default_str();
  app.add_option("--command", command, "the walk command (walk --help)")->capture_default_str();
  app.add_option("--control-period", period, "[s] control period, a multiple of 1 ms")
      ->capture_default_str()->check(ohrp::cli::Plausible("control_period"))
      ->check(ohrp::cli::InRange(0.001, 0.02));
  app.add_option("--beside", beside,
                 "a robot profile with a 'stand' stance, walked the same way beside HRP-1S "
                 "(\"\": none; skipped, said, when its model is not there)")
      ->capture_default_str();
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ohrp::model::InstallMujocoHandlers(nullptr);
  // what stopped the benchmark, exit code 2
  auto fail = [](const std::string& what) {
    std::fprintf(stderr, "bench_walk: %s\n", what.c_str());
    return 2;
  };

  Timed hrp;
  if (std::string e = TimeWalk({"HRP-1S", scene, "halfsit", "", ""}, command, period, &hrp);
      !e.empty())
    return fail(e);
  // the second robot: its profile's model must be there (../shared/external for G1)
  Timed other;
  std::string other_name;
  if (!beside.empty()) {
    ohrp::model::RobotProfile profile;
    std::string error;
    if (!ohrp::model::ReadProfile(beside, &profile, &error)) return fail("--beside " + error);
    other_name = std::filesystem::path(beside).stem().string();
    if (!std::filesystem::exists(profile.model)) {
      std::printf("(--beside %s: its model %s is not there; HRP-1S alone)\n", beside.c_str(),
                  profile.model.c_str());
      other_name.clear();
    } else if (std::string e = TimeWalk({other_name, beside, "stand", beside, "stand"}, command,
                                        period, &other);
               !e.empty()) {
      return fail(e);
    }
  }

  // the table, the walks' figures, the ratio to the control period (HRP-1S's)
  const double overhead = bench::ThreadCpuOverhead();
  const double median = bench::Quantile(hrp.walking.wall, 0.5),
               p99 = bench::Quantile(hrp.walking.wall, 0.99);
  std::printf("%-44s %26s   %26s\n", "one control cycle (update only) [us]",
              "wall: median  p90  p99", "thread CPU: median  p90  p99");
  bench::PrintRow("walk standing (balance's stance)", hrp.standing, overhead);
  bench::PrintRow("walk walking (generator + stabilizer + IK)", hrp.walking, overhead);
  if (!other_name.empty()) {
    bench::PrintRow((other_name + ": walk standing").c_str(), other.standing, overhead);
    bench::PrintRow((other_name + ": walk walking").c_str(), other.walking, overhead);
  }
  std::printf("(HRP-1S: %zu standing and %zu walking cycles; thread CPU clock read cost %.2f us "
              "subtracted)\n", hrp.standing.wall.size(), hrp.walking.wall.size(), overhead * 1e6);
  std::printf("%s", hrp.report.c_str());
  std::printf("walk: '%s', %d steps, control period %.1f ms; commands fingerprint %016llx over "
              "all %d cycles\n", command.c_str(), hrp.steps, period * 1e3,
              static_cast<unsigned long long>(hrp.fingerprint), hrp.cycles);
  if (!other_name.empty()) {
    std::printf("%s: %s", other_name.c_str(), other.report.c_str());
    std::printf("%s: %d steps; commands fingerprint %016llx over all %d cycles\n",
                other_name.c_str(), other.steps,
                static_cast<unsigned long long>(other.fingerprint), other.cycles);
  }
  std::printf("target: median under 100 us: %s; p99 under 300 us: %s\n",
              median < 100e-6 ? "met" : "NOT met", p99 < 300e-6 ? "met" : "NOT met");
  std::printf("ratio: %.2f (%.2f us / %.2f us)\n", median / period, median * 1e6, period * 1e6);
  return 0;
}
