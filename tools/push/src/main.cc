// ohrp_push: the largest push survived per direction, or the settling after a push, for one or
// more controllers side by side (see push/push.h and docs/scenarios.md).
#include "cli/command_line.h"
#include "cli/data_dir.h"
#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>

#include "push/push.h"

namespace {

using ohrp::push::Limit;

// the command line as given, before it is resolved into the options
struct Command {
  ohrp::push::PushOptions o;
  std::vector<std::string> controllers;
  std::vector<double> directions;
  std::vector<double> phases;
  std::vector<std::string> not_worse, require_settled;
  bool no_plot = false;
  std::vector<std::pair<size_t, size_t>> pairs;  // --require-not-worse A:B as indices
};

// the trials: controllers, directions, the bisection or settling, the push
void AddTrialOptions(CLI::App& app, Command& c) {
  ohrp::push::PushOptions& o = c.o;
  auto& controllers = c.controllers;
  auto& directions = c.directions;
  auto& phases = c.phases;
  app.add_option("--controller", controllers,
                 "controller command (program in build/bin and its arguments, one string); "
                 "repeat for a side-by-side table (default: posture)");
  app.add_option("--directions", directions, "push directions [deg] (default 0,45,...,315)")->delimiter(',');
  app.add_option("--max-impulse", o.max_impulse, "upper end of the bisection [N s]")->capture_default_str();
  app.add_option("--tolerance", o.tolerance, "bisection stops when the bracket is this narrow [N s]")
      ->capture_default_str();
  app.add_option("--settle", o.settle_impulse, "settle mode: one push of this impulse per direction [N s]");
  app.add_option("--settle-tolerance", o.settle_tolerance, "settle mode: base distance to its stance [m]")
      ->capture_default_str();
  app.add_option("--settle-fraction", o.settle_fraction,
                 "settle mode: ankle torque oscillation, fraction of its first peak")->capture_default_str();
  app.add_option("--settle-within", o.settle_within, "settle mode: settled when both times are below [s]")
      ->capture_default_str();
  app.add_option("--push-at", o.push_at, "simulated time of the push [s]")->capture_default_str();
  app.add_option("--phases", phases,
                 "several push times [s] (e.g. moments of a walk's gait: both feet down, lift-off, "
                 "early and late swing): one table per time in --out/at-T, and phases.md / "
                 "phases.csv, every controller x time x direction side by side")
      ->delimiter(',');
  app.add_option("--push-duration", o.push_duration, "duration of the push [s]")->capture_default_str();
  app.add_option("--observe", o.observe, "time after the push before standing is judged [s]")
      ->capture_default_str();
  app.add_option("--window", o.window, "length of the standing window at the end of the run [s]")
      ->capture_default_str();
}

// the scene, the jobs, the output and the requirements
void AddOutputOptions(CLI::App& app, Command& c) {
  ohrp::push::PushOptions& o = c.o;
  app.add_option("--scene", o.scene, "scene (MJCF, or a robot profile .yaml), relative to the repository root")->capture_default_str();
  app.add_option("--keyframe", o.keyframe, "initial state")->capture_default_str();
  app.add_option("--foot-sensors", o.foot_sensors,
                 "the soles' force/torque sensors whose forces say the feet carry the weight "
                 "(default: those of the scene's robot, e.g. rfsensor,lfsensor for HRP-1S)")
      ->delimiter(',');
  app.add_option("--jobs,-j", o.jobs, "trials at once (default: the number of cores)");
  app.add_option("--out", o.out_dir, "output folder (default: runs/push-<date>-<time>)");
  app.add_option("--require-not-worse", c.not_worse,
                 "A:B - exit 1 unless controller A survives at least B's impulse in every direction "
                 "(bisection mode; A and B as given to --controller)");
  app.add_option("--require-settled", c.require_settled,
                 "NAME - exit 1 unless controller NAME stands and settles within --settle-within in "
                 "every direction (settle mode)");
  app.add_flag("--no-plot", c.no_plot, "do not draw push.png");
  app.footer(
      "Exit codes: 0 done (and every --require-* holds), 1 a --require-* does not hold, a trial\n"
      "could not run or the report could not be written, 2 bad option, 130 interrupted.");
}

// the defaults (controllers, output folder, foot sensors) and every check: 2 on bad options,
// else -1
int ResolveOptions(Command& c) {
  ohrp::push::PushOptions& o = c.o;
  if (!c.controllers.empty()) o.controllers = c.controllers;
  if (!c.directions.empty()) o.directions = c.directions;
  o.plot = !c.no_plot;
  o.source_dir = ohrp::cli::DataDir();
  o.bin_dir = std::filesystem::canonical("/proc/self/exe").parent_path().string();
  if (o.out_dir.empty()) {
    char b[32];
    const std::time_t t = std::time(nullptr);
    std::strftime(b, sizeof(b), "%Y%m%d-%H%M%S", std::localtime(&t));
    o.out_dir = std::string("runs/push-") + b;
  }
  o.out_dir = std::filesystem::absolute(o.out_dir).lexically_normal().string();
  std::string error;
  if (!ohrp::push::ValidateOptions(o, &error)) {
    std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
    return 2;
  }
  const std::filesystem::path scene = std::filesystem::path(o.source_dir) / o.scene;
  if (o.foot_sensors.empty() &&
      !ohrp::push::FootSensorsOf(std::filesystem::path(o.scene).is_absolute() ? o.scene : scene.string(),
                                 &o.foot_sensors, &error)) {
    std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
    return 2;
  }
  return -1;
}

// --require-not-worse A:B names two of the controllers, --require-settled one: 2 if not, else -1
int ReadRequirements(Command& c) {
  const ohrp::push::PushOptions& o = c.o;
  for (const auto& spec : c.not_worse) {
    const auto colon = spec.find(':');
    auto find = [&](const std::string& name) {
      return static_cast<size_t>(std::find(o.controllers.begin(), o.controllers.end(), name) - o.controllers.begin());
    };
    const size_t a = colon == std::string::npos ? o.controllers.size() : find(spec.substr(0, colon));
    const size_t b = colon == std::string::npos ? o.controllers.size() : find(spec.substr(colon + 1));
    if (a >= o.controllers.size() || b >= o.controllers.size() || o.settle_impulse > 0) {
      std::fprintf(stderr, "ohrp_push: --require-not-worse '%s': write A:B with A and B two of the "
                           "--controller commands (bisection mode only)\n", spec.c_str());
      return 2;
    }
    c.pairs.push_back({a, b});
  }
  for (const auto& name : c.require_settled) {
    if (std::find(o.controllers.begin(), o.controllers.end(), name) == o.controllers.end() ||
        o.settle_impulse <= 0) {
      std::fprintf(stderr, "ohrp_push: --require-settled '%s': name one of the --controller commands "
                           "(settle mode only, with --settle IMPULSE)\n", name.c_str());
      return 2;
    }
  }
  return -1;
}

// one run per push time (--phases), each in its own folder; then the combined table: every time
// checked before anything runs; 2 on a bad time, 1 if a report cannot be written, else -1
int RunEachTime(const Command& c, const std::vector<double>& times,
                std::vector<std::vector<Limit>>* per_time) {
  const ohrp::push::PushOptions& o = c.o;
  const auto& phases = c.phases;
  std::string error;
  const std::string top = o.out_dir;
  for (double t : times) {  // every time checked before anything runs
    ohrp::push::PushOptions ot = o;
    ot.push_at = t;
    if (!ohrp::push::ValidateOptions(ot, &error)) {
      std::fprintf(stderr, "ohrp_push: --phases %g: %s\n", t, error.c_str());
      return 2;
    }
  }
  for (double t : times) {
    ohrp::push::PushOptions ot = o;
    ot.push_at = t;
    if (!phases.empty()) ot.out_dir = top + "/at-" + std::to_string(t).substr(0, std::to_string(t).find('.') + 3);
    per_time->push_back(ohrp::push::RunAll(ot));
    std::string markdown;
    if (!ohrp::push::WriteReport(ot, per_time->back(), &markdown, &error)) {
      std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
      return 1;
    }
    std::printf("%s", markdown.c_str());
    std::fprintf(stderr, "ohrp_push: wrote table.md, push.csv, push.json%s in %s\n",
                 ot.plot && ot.settle_impulse <= 0 ? ", push.png" : "", ot.out_dir.c_str());
  }
  if (!phases.empty() && !ohrp::push::WritePhases(o, times, *per_time, &error)) {
    std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
    return 1;
  }
  return -1;
}

// the verdict: every trial ran, each A survives at least what B does, the named controllers
// settle
int Verdict(const Command& c, const std::vector<double>& times, const std::vector<Limit>& results) {
  const ohrp::push::PushOptions& o = c.o;
  const auto& require_settled = c.require_settled;
  int rc = 0;
  for (const auto& l : results) {
    if (l.failed && l.detail == "interrupted") return 130;
    if (l.failed) {
      std::fprintf(stderr, "ohrp_push: %s at %g deg: %s\n", l.controller.c_str(), l.direction, l.detail.c_str());
      rc = 1;
    }
  }
  const size_t nd = o.directions.size();
  for (const auto& [a, b] : c.pairs) {
    for (size_t d = 0; d < nd * times.size(); ++d) {
      const size_t base = d / nd * nd * o.controllers.size();
      const auto& la = results[base + a * nd + d % nd];
      const auto& lb = results[base + b * nd + d % nd];
      if (la.largest < lb.largest && !(la.above_max && lb.above_max)) {
        std::fprintf(stderr, "ohrp_push: '%s' survives %.1f N s at %g deg, less than '%s' (%.1f N s)\n",
                     o.controllers[a].c_str(), la.largest, o.directions[d % nd], o.controllers[b].c_str(), lb.largest);
        rc = 1;
      }
    }
  }
  for (const auto& l : results) {
    if (std::find(require_settled.begin(), require_settled.end(), l.controller) == require_settled.end()) continue;
    if (!l.failed && !(l.settle.standing && l.settle.settled)) {
      std::fprintf(stderr, "ohrp_push: '%s' at %g deg: %s (base %.3f s, ankle torques %.3f s; within %.3g s required)\n",
                   l.controller.c_str(), l.direction, l.settle.standing ? "does not settle" : "fell",
                   l.settle.base_time, l.settle.torque_time, o.settle_within);
      rc = 1;
    }
  }
  return rc;
}

}  // namespace

int main(int argc, char** argv) {
  Command c;
  CLI::App app{
      "ohrp_push: how hard a push the standing robot survives. Per controller and direction\n"
      "(0 = +x forward, 90 = +y left), the largest impulse over --push-duration at the base after\n"
      "which the robot still stands, by bisection; or with --settle IMPULSE the time the base and the\n"
      "ankle torques take to settle after that push. Each trial is one headless lock-step run (soft\n"
      "soles, 1 ms physics, 5 ms control) starting from --keyframe. Writes table.md (also printed),\n"
      "push.csv, push.json and push.png into --out. Definitions: docs/scenarios.md."};
  AddTrialOptions(app, c);
  AddOutputOptions(app, c);
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  if (const int code = ResolveOptions(c); code >= 0) return code;
  if (const int code = ReadRequirements(c); code >= 0) return code;
  const std::vector<double> times = c.phases.empty() ? std::vector<double>{c.o.push_at} : c.phases;
  std::vector<std::vector<Limit>> per_time;
  if (const int code = RunEachTime(c, times, &per_time); code >= 0) return code;
  std::vector<Limit> results;
  for (const auto& r : per_time) results.insert(results.end(), r.begin(), r.end());
  return Verdict(c, times, results);
}
