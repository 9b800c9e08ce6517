// One push trial: a headless run through the runner library, then the standing and settling
// measures on its log (see push/push.h).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "push/push.h"
#include "runner/checks.h"
#include "runner/recovery.h"
#include "runner/runner.h"
#include "runner/scenario.h"

namespace fs = std::filesystem;

namespace ohrp::push {
namespace {

// "balance --foo 1" -> program balance, args [--foo, 1]; a word in single or double quotes
// keeps its spaces ("walk --command 'velocity 0.2 0 0 20'": one argument); no shell is involved
runner::ControllerSpec ParseCommand(const std::string& command) {
  runner::ControllerSpec spec;
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  char quote = 0;
  for (char c : command) {
    if (quote) {
      if (c == quote) quote = 0;
      else word += c;
    } else if (c == '\'' || c == '"') {
      quote = c;
      in_word = true;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
    } else {
      word += c;
      in_word = true;
    }
  }
  if (in_word) words.push_back(word);
  for (const std::string& w : words) {
    if (spec.program.empty()) spec.program = w;
    else spec.args.push_back(w);
  }
  return spec;
}

// a folder name for a controller command
std::string Slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return out;
}

}  // namespace

bool ValidateOptions(const PushOptions& o, std::string* error) {
  auto bad = [&](const std::string& why) {
    *error = why;
    return false;
  };
  if (o.controllers.empty()) return bad("give at least one --controller");
  for (const auto& c : o.controllers) {
    if (ParseCommand(c).program.empty()) return bad("--controller '" + c + "' is empty");
    if (std::count(c.begin(), c.end(), '\'') % 2 || std::count(c.begin(), c.end(), '"') % 2)
      return bad("--controller '" + c + "' has a quote that is not closed");
  }
  if (o.directions.empty()) return bad("give at least one direction");
  for (double d : o.directions)
    if (!std::isfinite(d)) return bad("directions must be finite numbers of degrees");
  if (!(o.push_at >= 0.7) || !std::isfinite(o.push_at))
    return bad("--push-at must be >= 0.7 s (the stance before the push is measured over 0.5 s)");
  if (!(o.push_duration > 0) || o.push_duration > 1) return bad("--push-duration must be in (0, 1] s");
  if (!(o.observe > 0) || !(o.window > 0) || o.observe > 60 || o.window > 60)
    return bad("--observe and --window must be in (0, 60] s");
  if (!(o.max_impulse > 0) || o.max_impulse > 1e4) return bad("--max-impulse must be in (0, 10000] N s");
  if (!(o.tolerance > 0) || o.tolerance >= o.max_impulse)
    return bad("--tolerance must be > 0 and below --max-impulse");
  if (!(o.settle_impulse >= 0) || o.settle_impulse > 1e4) return bad("--settle must be in [0, 10000] N s");
  if (o.settle_impulse > 0 && o.settle_within > o.observe + o.window)
    return bad("--settle-within must not exceed --observe + --window (the run ends there)");
  if (!(o.settle_tolerance > 0) || !(o.settle_fraction > 0 && o.settle_fraction < 1) ||
      !(o.settle_within > 0))
    return bad("--settle-tolerance must be > 0, --settle-fraction in (0, 1), --settle-within > 0");
  if (o.jobs < 0 || o.jobs > 256) return bad("--jobs must be in [0, 256]");
  const fs::path scene = fs::path(o.scene).is_absolute() ? fs::path(o.scene) : fs::path(o.source_dir) / o.scene;
  if (!fs::exists(scene)) return bad("the scene '" + scene.string() + "' does not exist");
  for (const auto& c : o.controllers) {
    const auto prog = ParseCommand(c).program;
    const fs::path p = prog.find('/') == std::string::npos ? fs::path(o.bin_dir) / prog : fs::path(prog);
    if (!fs::exists(p))
      return bad("controller program '" + p.string() + "' not found (build it, or give a path)");
  }
  return true;
}

Trial RunTrial(const PushOptions& o, const std::string& controller, double direction,
               double impulse, int index) {
  Trial t;
  t.controller = controller;
  t.direction = direction;
  t.impulse = impulse;
  char name[128];
  std::snprintf(name, sizeof(name), "%s_d%03.0f_i%06.2f", Slug(controller).c_str(), direction, impulse);
  t.dir = (fs::path(o.out_dir) / "trials" / name).string();

  // the run: start in half-sitting, push, observe
  runner::Scenario s;
  s.name = "push" + std::to_string(index);
  s.file = "(ohrp_push trial)";
  s.scene = o.scene;
  s.keyframe = o.keyframe;
  s.physics_dt = 0.001;
  s.control_period = 0.005;
  s.integrator = "euler";
  s.contact = "soft";
  const double push_end = o.push_at + o.push_duration;
  s.duration = push_end + o.observe + o.window;
  s.controllers.push_back(ParseCommand(controller));
  runner::PushSpec p;
  p.at = o.push_at;
  p.duration = o.push_duration;
  p.direction_deg = direction;
  p.impulse = impulse;
  s.pushes.push_back(p);
  runner::RunOptions ro;
  ro.out_dir = t.dir;
  ro.source_dir = o.source_dir;
  ro.bin_dir = o.bin_dir;
  ro.plot = false;
  ro.echo = false;
  ro.report = false;
  const int rc = runner::RunScenario(s, ro);
  if (rc == runner::kRunInterrupted || rc == runner::kRunUsage) {
    t.detail = rc == runner::kRunUsage ? "the run could not start (see " + t.dir + ")" : "interrupted";
    return t;
  }

  // how the processes ended: a diverged simulation is a fall, a dead controller spoils the trial
  nlohmann::json summary, sim = nlohmann::json::object();
  try {
    std::ifstream(t.dir + "/summary.json") >> summary;
    std::ifstream in(t.dir + "/sim_summary.json");
    if (in) in >> sim;
  } catch (const std::exception& e) {
    t.detail = std::string("unreadable summary: ") + e.what();
    return t;
  }
  // a completed run needs the controller to have ended cleanly; a fall (sim_host's fall watch,
  // sim_host/fall.h: exit 6, the summary's "fall") is a result, not an error, and so is a
  // diverged run (a robot falling where only the soles collide once sank through the floor until
  // the energy watch stopped sim_host); the controller may then end with an error of its own
  const std::string outcome = sim.value("outcome", std::string("no summary"));
  // a controller that saw the robot fall ends with exit 8 (controllers/runner.h): a fall too,
  // whatever sim_host then made of the controller leaving
  std::string fell_by;
  for (const auto& proc : summary["processes"])
    if (proc["name"] != "sim_host" && proc["exit_code"] == 8) fell_by = proc["name"].get<std::string>();
  if (!fell_by.empty()) {
    t.ok = true;
    t.standing = false;
    t.detail = "controller '" + fell_by + "' detected a fall (exit 8; see " + t.dir + ")";
    return t;
  }
  // a controller that could not complete its task (exit 9: e.g. a walk whose arms the push threw
  // into the body) is judged like the others, by standing; its reason is kept in the detail
  std::string unfinished;
  for (const auto& proc : summary["processes"])
    if (proc["name"] != "sim_host" && proc["exit_code"] == 9)
      unfinished = "; controller '" + proc["name"].get<std::string>() +
                   "' did not complete its task (exit 9, see " + t.dir + ")";
  const bool fell = sim.contains("fall") && sim["fall"].is_object();
  const bool diverged = outcome == "diverged" || fell;
  if (outcome != "completed" && !diverged) {
    t.detail = "sim_host: " + outcome + " " + sim.value("detail", std::string()) + " (see " + t.dir + ")";
    return t;
  }
  for (const auto& proc : summary["processes"]) {
    if (!diverged && proc["name"] != "sim_host" && proc["exit_code"] != 0 && proc["exit_code"] != 9) {
      t.detail = "controller '" + proc["name"].get<std::string>() + "' exited with " +
                 std::to_string(proc["exit_code"].get<int>()) + " (see " + t.dir + ")";
      return t;
    }
  }
  datalog::Table log;
  std::string error;
  if (!log.Load(t.dir + "/log.csv", &error)) {
    t.detail = error;
    return t;
  }
  t.ok = true;

  // standing, then settling
  runner::StandingSpec st;
  st.stance_at = o.push_at;
  st.after = push_end + o.observe;
  st.sensors = o.foot_sensors;
  runner::StandingResult sr;
  if (!runner::MeasureStanding(log, sim, st, &sr, &error)) {
    t.ok = false;
    t.detail = error;
    return t;
  }
  t.standing = sr.standing && !diverged;
  char fell_at[48];
  std::snprintf(fell_at, sizeof(fell_at), "fell at t=%.3f s: ", fell ? sim["fall"].value("time", 0.0) : 0.0);
  t.detail = fell       ? fell_at + sim["fall"].value("cause", std::string())
             : diverged ? "sim_host stopped at t=" + std::to_string(sim.value("sim_time", 0.0)) +
                              " s: " + sim.value("detail", std::string()).substr(0, 60) + "..."
                        : sr.why;
  t.detail += unfinished;
  t.lowest_height = sr.lowest_height;
  t.stance_height = sr.stance_height;
  t.largest_tilt = sr.largest_tilt;
  if (o.settle_impulse > 0) {
    runner::SettleSpec ss;
    ss.sensors = o.foot_sensors;
    ss.at = o.push_at;
    ss.duration = o.push_duration;
    ss.tolerance = o.settle_tolerance;
    ss.fraction = o.settle_fraction;
    ss.within = o.settle_within;
    runner::SettleResult r;
    if (runner::MeasureSettling(log, ss, &r, &error)) {
      t.base_time = r.base_time;
      t.torque_time = r.torque_time;
      t.first_peak = r.first_peak;
      t.base_excursion = r.base_excursion;
      t.settled = r.settled;
    } else {
      t.detail += "; settling: " + error;
    }
  }
  // keep the folders small: the log of a bisection trial is not needed afterwards
  if (o.settle_impulse <= 0) fs::remove(t.dir + "/log.csv");
  return t;
}

}  // namespace ohrp::push
