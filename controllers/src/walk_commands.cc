// The walk controller's inputs: command lines and the YAML parameter file (see walk.h).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

#include "cli/plausible.h"
#include "controllers/walk.h"
#include "walking/footstep_file.h"

namespace ohrp::controllers {
namespace {

constexpr double kDeg = M_PI / 180;

std::string At(const std::string& path, const YAML::Node& node) {
  return path + ":" + std::to_string(node.Mark().line + 1) + ": ";
}

ConfigStatus ApplyWalkParams(const YAML::Node& root, const std::string& path, WalkOptions* o,
                             const std::vector<std::string>& keep);

}  // namespace

const char* WalkCommandHelp() {
  return "Commands (--command, repeatable, walked in turn; each from the stance the last ends in):\n"
         "  goal X Y YAW_DEG          go to (X, Y) [m] turned by YAW_DEG [deg], in the frame of\n"
         "                            the feet's middle (x forward, y left), fewest steps\n"
         "  velocity VX VY WZ_DEG T   walk at (VX, VY) [m/s] turning WZ_DEG [deg/s] for T [s],\n"
         "                            then close the feet\n"
         "  steps FILE                follow a footstep file (docs/footsteps.md: YAML or CSV)\n"
         "  wait T                    stand for T [s]\n"
         "  random N SEED             N steps drawn at random within the step limits (turns both\n"
         "                            ways, back and side steps, stops; the same SEED, the same\n"
         "                            steps), then close the feet\n"
         "SIGUSR1 stops the walk under way (the feet close; later commands are dropped).\n";
}

bool ParseWalkCommand(const std::string& text, WalkCommand* c, std::string* error) {
  std::istringstream in(text);
  std::string verb;
  in >> verb;
  *c = WalkCommand{};
  c->text = text;
  const auto numbers = [&](int n, double* out) {
    for (int i = 0; i < n; ++i) {
      if (!(in >> out[i]) || !std::isfinite(out[i])) return false;
    }
    std::string extra;
    return !(in >> extra);
  };
  double v[4] = {0, 0, 0, 0};
  if (verb == "goal") {
    c->kind = WalkCommand::Kind::kGoal;
    if (!numbers(3, v)) {
      *error = "\"" + text + "\": goal takes X Y YAW_DEG (three numbers, e.g. goal 1.0 0 90)";
      return false;
    }
    c->x = v[0], c->y = v[1], c->yaw = v[2] * kDeg;
    return true;
  }
  if (verb == "velocity") {
    c->kind = WalkCommand::Kind::kVelocity;
    if (!numbers(4, v) || !(v[3] > 0) || v[3] > 36000) {
      *error = "\"" + text + "\": velocity takes VX VY WZ_DEG SECONDS (SECONDS in (0, 36000], "
               "e.g. velocity 0.2 0 0 10)";
      return false;
    }
    c->x = v[0], c->y = v[1], c->yaw = v[2] * kDeg, c->time = v[3];
    return true;
  }
  if (verb == "wait") {
    c->kind = WalkCommand::Kind::kWait;
    if (!numbers(1, v) || !(v[0] >= 0) || v[0] > 36000) {
      *error = "\"" + text + "\": wait takes SECONDS in [0, 36000] (e.g. wait 2)";
      return false;
    }
    c->time = v[0];
    return true;
  }
  if (verb == "steps") {
    c->kind = WalkCommand::Kind::kSteps;
    if (!(in >> c->file)) {
      *error = "\"" + text + "\": steps takes a footstep file (e.g. steps scenarios/steps/mixed.yaml)";
      return false;
    }
    std::string extra;
    if (in >> extra) {
      *error = "\"" + text + "\": steps takes one file name (no spaces)";
      return false;
    }
    return true;
  }
  if (verb == "random") {
    c->kind = WalkCommand::Kind::kRandom;
    if (!numbers(2, v) || !(v[0] >= 1 && v[0] <= 10000) || v[0] != std::floor(v[0]) ||
        !(v[1] >= 0 && v[1] <= 4294967295.0) || v[1] != std::floor(v[1])) {
      *error = "\"" + text + "\": random takes STEPS SEED (whole numbers, STEPS in [1, 10000], "
               "SEED in [0, 4294967295], e.g. random 20 7)";
      return false;
    }
    c->count = static_cast<int>(v[0]);
    c->seed = static_cast<unsigned>(v[1]);
    return true;
  }
  *error = "unknown walk command \"" + text + "\": use goal, velocity, steps, wait or random";
  return false;
}

bool PlanWalkCommand(const WalkCommand& c, const walking::FeetPose& feet,
                     const walking::StepLimits& lim, double step_time,
                     std::vector<walking::Footstep>* steps, std::string* note, std::string* error) {
  constexpr double kRandomStopShare = 0.15;  // the share of a random walk's steps that are stops
  steps->clear();
  std::string why;
  switch (c.kind) {
    case WalkCommand::Kind::kGoal:
      *steps = walking::PlanToGoal(feet, c.x, c.y, c.yaw, lim, &why);
      break;
    case WalkCommand::Kind::kVelocity:
      // the velocity is in the stance's mid frame; the generator's step time
      *steps = walking::PlanVelocity(feet, c.x, c.y, c.yaw, c.time, step_time, lim, note);
      break;
    case WalkCommand::Kind::kSteps:
      // a footstep file is input: out of the limits or the robot's physics, a bad command, with
      // the file, line, key and range
      if (!walking::ReadFootstepFile(c.file, feet, lim, steps, error)) return false;
      break;
    case WalkCommand::Kind::kRandom:
      *steps = walking::PlanRandom(feet, c.count, c.seed, lim, kRandomStopShare, &why);
      break;
    case WalkCommand::Kind::kWait:
      break;
  }
  if (!why.empty()) {
    *error = "\"" + c.text + "\": " + why;
    return false;
  }
  if (const std::string e = walking::CheckSteps(feet, *steps, lim); !e.empty()) {
    *error = "\"" + c.text + "\" cannot be walked: " + e;
    return false;
  }
  return true;
}

ConfigStatus LoadWalkParams(const std::string& path, WalkOptions* o,
                            const std::vector<std::string>& keep) {
  std::ifstream f(path);
  if (!f) return ConfigStatus::Fail(ConfigError::kFile, path + ": cannot be read");
  std::stringstream text;
  text << f.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::Exception& e) {
    return ConfigStatus::Fail(ConfigError::kFile,
                              path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap())
    return ConfigStatus::Fail(ConfigError::kFile, path + ": expected a map of parameters (docs/walking.md)");
  return ApplyWalkParams(root, path, o, keep);
}

ConfigStatus LoadProfileWalkParams(const std::string& profile, WalkOptions* o,
                                   const std::vector<std::string>& keep) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(profile);
  } catch (const YAML::Exception& e) {
    return ConfigStatus::Fail(ConfigError::kFile,
                              profile + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap() || !root["walking"]) return ConfigStatus::Ok();
  if (!root["walking"].IsMap())
    return ConfigStatus::Fail(ConfigError::kFile, At(profile, root["walking"]) +
                                                      "walking: expected a map of walk's parameters (docs/walking.md)");
  return ApplyWalkParams(root["walking"], profile, o, keep);
}

namespace {

// the parameters of map `root` (a --params file, or a profile's walking:) into `o`, but for
// those in `keep` (the command line's), which are checked and said to be overridden
ConfigStatus ApplyWalkParams(const YAML::Node& root, const std::string& path, WalkOptions* o,
                             const std::vector<std::string>& keep) {
  // every key and where its value goes
  walking::GaitOptions& g = o->gait;
  walking::StepLimits& l = o->limits;
  const std::map<std::string, double*> keys = {
      {"step_time", &g.step_time}, {"double_support_ratio", &g.double_support_ratio},
      {"step_height", &g.step_height}, {"vertical_fraction", &g.vertical_fraction},
      {"start_delay", &g.start_delay}, {"start_time", &g.start_time}, {"end_time", &g.end_time},
      {"zmp_forward", &g.zmp_forward}, {"preview_time", &o->preview.preview_time},
      {"preview_q", &o->preview.q}, {"preview_r", &o->preview.r}, {"com_lower", &o->com_lower},
      {"lower_time", &o->lower_time}, {"step_search", &o->step_search},
      {"swing_tilt_compensation", &o->swing_tilt_compensation},
      {"inertia_feedforward", &o->inertia_feedforward}, {"swing_zmp", &o->swing_zmp},
      {"max_forward", &l.max_forward},
      {"max_backward", &l.max_backward}, {"max_side", &l.max_side}, {"min_width", &l.min_width},
      {"max_turn_deg", nullptr}, {"max_turn_in_deg", nullptr}, {"clearance", &l.clearance},
      {"max_stride_change", &l.max_stride_change}, {"start_push", nullptr},
      {"start_rock", nullptr}, {"stop_rock", nullptr}};
  // the quantity of each key with a row in the plausible-range table
  static const std::map<std::string, const char*> kQuantity = {
      {"step_time", "step_time"},       {"double_support_ratio", "fraction"},
      {"step_height", "swing_apex"},    {"vertical_fraction", "fraction"},
      {"start_delay", "wait"},          {"start_time", "double_support"},
      {"end_time", "double_support"},   {"com_lower", "height"},
      {"lower_time", "time_constant"},  {"step_search", "distance"},
      {"max_forward", "stride"},        {"max_backward", "stride"},
      {"max_side", "stride"},           {"min_width", "stride"},
      {"clearance", "distance"},        {"max_stride_change", "stride"},
      {"preview_time", "duration"},
      {"swing_tilt_compensation", "fraction"}, {"inertia_feedforward", "gain_scale"},
      {"swing_zmp", "fraction"}};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    const auto it = keys.find(key);
    if (it == keys.end()) {
      std::string known;
      for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k.first;
      return ConfigStatus::Fail(ConfigError::kFile,
                                At(path, kv.first) + "unknown key '" + key + "' (known: " + known + ")");
    }
    double v = 0;
    try {
      v = kv.second.as<double>();
    } catch (const YAML::Exception&) {
      return ConfigStatus::Fail(ConfigError::kFile, At(path, kv.second) + "'" + key +
                                                        "' must be a number");
    }
    if (!std::isfinite(v))
      return ConfigStatus::Fail(ConfigError::kFile, At(path, kv.second) + "'" + key + "' must be finite");
    // the plausible range of the quantity the key is (cli/plausible.h): exit 2 with the range
    if (const auto q = kQuantity.find(key); q != kQuantity.end()) {
      const std::string where = At(path, kv.second) + key;
      if (std::string e = cli::CheckPlausible(q->second, v, where); !e.empty())
        return ConfigStatus::Fail(ConfigError::kOption, e);
    }
    if (std::find(keep.begin(), keep.end(), key) != keep.end()) {
      std::fprintf(stderr, "walk: %s%s: %g overridden by the command line\n",
                   At(path, kv.second).c_str(), key.c_str(), v);
      continue;
    }
    o->given.push_back(key);
    if (key == "start_push") g.start_push = v != 0;
    else if (key == "start_rock") g.start_rock = v != 0;
    else if (key == "stop_rock") g.stop_rock = v != 0;
    else if (key == "max_turn_deg") l.max_turn = v * kDeg;
    else if (key == "max_turn_in_deg") l.max_turn_in = v * kDeg;
    else *it->second = v;
  }
  return ConfigStatus::Ok();
}

}  // namespace

}  // namespace ohrp::controllers
