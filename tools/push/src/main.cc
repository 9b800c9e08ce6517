// ohrp_push: the largest push survived per direction, or the settling after a push, for one or
// more controllers side by side (see push/push.h and docs/scenarios.md).
#include "cli/command_line.h"
#include "cli/data_dir.h"
#include <algorithm>
#include <cmath>
#include <ctime>
#include <filesystem>

#include "push/push.h"

int main(int argc, char** argv) {
  ohrp::push::PushOptions o;
  std::vector<std::string> controllers;
  std::vector<double> directions;
  std::vector<double> phases;
  std::vector<std::string> not_worse, require_settled;
  bool no_plot = false;
  CLI::App app{
      "ohrp_push: how hard a push the standing robot survives. Per controller and direction\n"
      "(0 = +x forward, 90 = +y left), the largest impulse over --push-duration at the base after\n"
      "which the robot still stands, by bisection; or with --settle IMPULSE the time the base and the\n"
      "ankle torques take to settle after that push. Each trial is one headless lock-step run (soft\n"
      "soles, 1 ms physics, 5 ms control) starting from --keyframe. Writes table.md (also printed),\n"
      "push.csv, push.json and push.png into --out. Definitions: docs/scenarios.md."};
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
  app.add_option("--scene", o.scene, "scene (MJCF, or a robot profile .yaml), relative to the repository root")->capture_default_str();
  app.add_option("--keyframe", o.keyframe, "initial state")->capture_default_str();
  app.add_option("--foot-sensors", o.foot_sensors,
                 "the soles' force/torque sensors whose forces say the feet carry the weight "
                 "(default: those of the scene's robot, e.g. rfsensor,lfsensor for HRP-1S)")
      ->delimiter(',');
  app.add_option("--jobs,-j", o.jobs, "trials at once (default: the number of cores)");
  app.add_option("--out", o.out_dir, "output folder (default: runs/push-<date>-<time>)");
  app.add_option("--require-not-worse", not_worse,
                 "A:B - exit 1 unless controller A survives at least B's impulse in every direction "
                 "(bisection mode; A and B as given to --controller)");
  app.add_option("--require-settled", require_settled,
                 "NAME - exit 1 unless controller NAME stands and settles within --settle-within in "
                 "every direction (settle mode)");
  app.add_flag("--no-plot", no_plot, "do not draw push.png");
  app.footer(
      "Exit codes: 0 done (and every --require-* holds), 1 a --require-* does not hold, a trial\n"
      "could not run or the report could not be written, 2 bad option, 130 interrupted.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;

  if (!controllers.empty()) o.controllers = controllers;
  if (!directions.empty()) o.directions = directions;
  o.plot = !no_plot;
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
  // A:B pairs name two of the controllers
  std::vector<std::pair<size_t, size_t>> pairs;
  for (const auto& spec : not_worse) {
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
    pairs.push_back({a, b});
  }
  for (const auto& name : require_settled) {
    if (std::find(o.controllers.begin(), o.controllers.end(), name) == o.controllers.end() ||
        o.settle_impulse <= 0) {
      std::fprintf(stderr, "ohrp_push: --require-settled '%s': name one of the --controller commands "
                           "(settle mode only, with --settle IMPULSE)\n", name.c_str());
      return 2;
    }
  }

  // one run per push time (--phases), each in its own folder; then the combined table
  std::vector<double> times = phases.empty() ? std::vector<double>{o.push_at} : phases;
  std::vector<ohrp::push::Limit> results;
  std::vector<std::vector<ohrp::push::Limit>> per_time;
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
    per_time.push_back(ohrp::push::RunAll(ot));
    std::string markdown;
    if (!ohrp::push::WriteReport(ot, per_time.back(), &markdown, &error)) {
      std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
      return 1;
    }
    std::printf("%s", markdown.c_str());
    std::fprintf(stderr, "ohrp_push: wrote table.md, push.csv, push.json%s in %s\n",
                 ot.plot && ot.settle_impulse <= 0 ? ", push.png" : "", ot.out_dir.c_str());
  }
  if (!phases.empty() && !ohrp::push::WritePhases(o, times, per_time, &error)) {
    std::fprintf(stderr, "ohrp_push: %s\n", error.c_str());
    return 1;
  }
  for (const auto& r : per_time) results.insert(results.end(), r.begin(), r.end());

  // the verdict: every trial ran, each A survives at least what B does, the named controllers
  // settle
  int rc = 0;
  for (const auto& l : results) {
    if (l.failed && l.detail == "interrupted") return 130;
    if (l.failed) {
      std::fprintf(stderr, "ohrp_push: %s at %g deg: %s\n", l.controller.c_str(), l.direction, l.detail.c_str());
      rc = 1;
    }
  }
  const size_t nd = o.directions.size();
  for (const auto& [a, b] : pairs) {
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
