// Scenario parsing (see scenario.h): every key and value is checked here, before anything runs.
#include "runner/scenario.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "check_parse.h"
#include "cli/plausible.h"
#include "runner/check_keys.h"
#include "runner/commands.h"
#include "pushes.h"
#include "sim_host/effects.h"
#include "scenario_params.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

const std::set<std::string> kTopKeys = {
    "name", "description", "scene", "keyframe", "duration", "physics_dt", "control_period",
    "integrator", "realtime", "on_controller_loss", "controller_timeout", "wall_timeout",
    "log_every", "sim_args", "controllers", "checks", "plot_joints", "plot_torques", "contact",
    "contact_params", "joint_params", "effects", "pushes", "camera_rate", "expect_fall", "on_fall",
    "fall_allow_contact"};
const std::set<std::string> kControllerKeys = {"program", "args"};

// bounds of the run's numbers (the time steps: cli/plausible.h)
constexpr double kMaxCameraRate = 1000.0;    // [frames per simulated s], sim_host's bounds: [0.1, 1000]
constexpr double kMaxDuration = 1e5;         // [s] simulated, about 28 hours
constexpr double kMaxControllerTimeout = 3600;  // [s] wall
constexpr double kMaxWallTimeout = 1e6;      // [s] wall
constexpr long long kMaxLogEvery = 1000000;

// reads root[key] with `read` when present; false with the file, line and key otherwise
template <typename Read>
bool Optional(const YAML::Node& root, const char* key, const std::string& path,
              std::string* error, Read read) {
  const YAML::Node n = root[key];
  if (!n) return true;
  std::string why;
  if (read(n, &why)) return true;
  *error = AtKey(path, root, key) + key + ": " + why;
  return false;
}

// a number in (lo, hi] or [lo, hi]
auto NumberIn(double* out, double lo, double hi, bool lo_open, const char* unit) {
  return [=](const YAML::Node& n, std::string* why) {
    if (!ReadNumber(n, out, why)) return false;
    if (*out < lo || (lo_open && *out == lo) || *out > hi) {
      char b[160];
      std::snprintf(b, sizeof(b), "must be in %s%g, %g] %s, not %g", lo_open ? "(" : "[", lo, hi,
                    unit, *out);
      *why = b;
      return false;
    }
    return true;
  };
}

// a number in the plausible range of `quantity` (cli/plausible.h)
auto PlausibleNumber(double* out, const char* quantity) {
  return [=](const YAML::Node& n, std::string* why) {
    if (!ReadNumber(n, out, why)) return false;
    const cli::PlausibleRange* r = cli::FindPlausible(quantity);
    if (r && cli::IsPlausible(*r, *out)) return true;
    *why = n.Scalar() + " is outside " + (r ? cli::PlausibleRangeText(*r) : std::string("?"));
    return false;
  };
}

auto NonEmptyText(std::string* out) {
  return [=](const YAML::Node& n, std::string* why) {
    if (!ReadText(n, out, why)) return false;
    if (out->empty()) *why = "must not be empty";
    return !out->empty();
  };
}

auto TextList(std::vector<std::string>* out) {
  return [=](const YAML::Node& n, std::string* why) { return ReadTextList(n, out, why); };
}

auto Choice(std::string* out, std::vector<std::string> choices) {
  return [=](const YAML::Node& n, std::string* why) { return ReadChoice(n, choices, out, why); };
}

// a name fit for a folder and a segment name
bool PlainName(const std::string& name) {
  if (name.empty() || name.size() > 100) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return true;
}

// every item of the list `key` of `map` has known placeholders only ({out}, commands.h); false
// with the item's line, `where` and the key otherwise
bool KnownPlaceholders(const YAML::Node& map, const char* key, const std::string& path,
                       const std::string& where, std::string* error) {
  const YAML::Node list = map[key];
  for (size_t k = 0; list && list.IsSequence() && k < list.size(); ++k) {
    const std::string why = UnknownPlaceholder(list[k].Scalar());
    if (why.empty()) continue;
    *error = At(path, list[k]) + where + key + "[" + std::to_string(k) + "]: " + why;
    return false;
  }
  return true;
}

//---------------- sections ----------------

// the scalar keys of the run, each in its range
bool ReadRun(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  long long log_every = s->log_every;
  const bool ok =
      Optional(root, "name", path, error, NonEmptyText(&s->name)) &&
      Optional(root, "description", path, error,
               [&](const YAML::Node& n, std::string* why) { return ReadText(n, &s->description, why); }) &&
      Optional(root, "scene", path, error, NonEmptyText(&s->scene)) &&
      Optional(root, "keyframe", path, error, NonEmptyText(&s->keyframe)) &&
      Optional(root, "physics_dt", path, error, PlausibleNumber(&s->physics_dt, "physics_dt")) &&
      Optional(root, "control_period", path, error, PlausibleNumber(&s->control_period, "control_period")) &&
      Optional(root, "duration", path, error, NumberIn(&s->duration, 0, kMaxDuration, true, "s")) &&
      Optional(root, "camera_rate", path, error,
               NumberIn(&s->camera_rate, 0.1, kMaxCameraRate, false, "frames per simulated s")) &&
      Optional(root, "integrator", path, error, Choice(&s->integrator, {"euler", "rk4", "implicit"})) &&
      Optional(root, "realtime", path, error,
               [&](const YAML::Node& n, std::string* why) { return ReadBool(n, &s->realtime, why); }) &&
      Optional(root, "on_controller_loss", path, error,
               Choice(&s->on_controller_loss, {"end", "wait", "continue"})) &&
      Optional(root, "controller_timeout", path, error,
               NumberIn(&s->controller_timeout, 0, kMaxControllerTimeout, true, "s")) &&
      Optional(root, "wall_timeout", path, error,
               NumberIn(&s->wall_timeout, 0, kMaxWallTimeout, false, "s (0: derived)")) &&
      Optional(root, "log_every", path, error,
               [&](const YAML::Node& n, std::string* why) {
                 if (!ReadInteger(n, &log_every, why)) return false;
                 if (log_every >= 1 && log_every <= kMaxLogEvery) return true;
                 *why = "must be in [1, " + std::to_string(kMaxLogEvery) + "] control cycles";
                 return false;
               }) &&
      Optional(root, "contact", path, error, Choice(&s->contact, {"soft", "native", "rigid", "auto"})) &&
      Optional(root, "sim_args", path, error, TextList(&s->sim_args)) &&
      Optional(root, "plot_joints", path, error, TextList(&s->plot_joints)) &&
      Optional(root, "plot_torques", path, error, TextList(&s->plot_torques)) &&
      Optional(root, "expect_fall", path, error,
               [&](const YAML::Node& n, std::string* why) { return ReadBool(n, &s->expect_fall, why); }) &&
      Optional(root, "on_fall", path, error, Choice(&s->on_fall, {"end", "continue"})) &&
      Optional(root, "fall_allow_contact", path, error, TextList(&s->fall_allow_contact)) &&
      KnownPlaceholders(root, "sim_args", path, "", error);
  if (!ok) return false;
  s->log_every = static_cast<int>(log_every);

  // the scene is required; the control period is whole physics steps; the run has a cycle
  const std::string file = "scenario '" + path + "': ";
  if (!root["scene"]) {
    *error = file + "'scene' is required (an MJCF file, OpenHRP VRML .wrl or robot profile .yaml, e.g. mjcf/hrp1s/scene_flat.xml)";
    return false;
  }
  s->scene_line = root["scene"].Mark().line + 1;
  if (s->physics_dt > 0 && s->control_period > 0) {
    const double ratio = s->control_period / s->physics_dt;
    if (ratio < 1 - 1e-9 || std::fabs(ratio - std::round(ratio)) > 1e-6) {
      *error = AtKey(path, root, root["control_period"] ? "control_period" : "physics_dt") +
               "control_period: " + std::to_string(s->control_period) +
               " s must be a whole multiple of physics_dt (" + std::to_string(s->physics_dt) + " s)";
      return false;
    }
  }
  if (s->control_period > 0 && s->duration < s->control_period) {
    *error = AtKey(path, root, "duration") + "duration: " +
             std::to_string(s->duration) + " s is shorter than one control period (" +
             std::to_string(s->control_period) + " s)";
    return false;
  }
  if (!PlainName(s->name)) {
    *error = AtKey(path, root, "name") + "name: '" + s->name +
             "' must be letters, digits, '_', '-' or '.' (it names the output folder and the segment)";
    return false;
  }
  return true;
}

// effects: NAME: on|off, contact:BODY1/BODY2: on|off, noise.KIND: STD, noise.seed: N, each
// checked by sim_host's own parser (docs/effects.md); passed on as sim_args --effects
bool ReadEffects(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const YAML::Node n = root["effects"];
  if (!n.IsMap()) {
    *error = AtKey(path, root, "effects") + "'effects' must be a mapping, e.g. {noise: on, gravity: off}";
    return false;
  }
  std::string list;
  for (const auto& kv : n) {
    std::string key, value, why;
    if (!ReadText(kv.first, &key, &why) || !ReadText(kv.second, &value, &why)) {
      *error = At(path, kv.first) + "effects: each entry must be NAME: on, off or a number";
      return false;
    }
    if (key.find_first_of(",=") != std::string::npos || value.find_first_of(",=") != std::string::npos) {
      *error = At(path, kv.first) + "effects: '" + key + "' has a ',' or '='";
      return false;
    }
    sim::EffectRequests requests;
    if (!sim::ParseEffectRequests(key + "=" + value, &requests, &why)) {
      *error = At(path, kv.first) + why;
      return false;
    }
    s->effects[key] = value;
    list += (list.empty() ? "" : ",") + key + "=" + value;
  }
  if (!list.empty()) s->sim_args.insert(s->sim_args.begin(), {"--effects", list});
  return true;
}

// controllers: a list of {program, args}; `controllers: []` runs without one
bool ReadControllers(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const YAML::Node list = root["controllers"];
  if (!list) {
    *error = "scenario '" + path + "': 'controllers' is missing: list them ({program, args}), or "
             "write 'controllers: []' to run without one (the joints hold their initial pose)";
    return false;
  }
  if (!list.IsSequence()) {
    *error = AtKey(path, root, "controllers") + "'controllers' must be a list of {program, args} (or [] for none)";
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node c = list[i];
    const std::string where = "controllers[" + std::to_string(i) + "]: ";
    if (!c.IsMap()) {
      *error = At(path, c) + where + "must be a mapping, e.g. {program: posture, args: [--ramp, \"2.0\"]}";
      return false;
    }
    if (!KnownKeysOnly(c, kControllerKeys, path, where, error)) return false;
    ControllerSpec spec;
    spec.line = c.Mark().line + 1;
    std::string why;
    if (!c["program"]) {
      *error = At(path, c) + where + "'program' is required (a program in build/bin or a path)";
      return false;
    }
    if (!ReadText(c["program"], &spec.program, &why) || spec.program.empty()) {
      *error = AtKey(path, c, "program") + where + "program: " + (why.empty() ? "must not be empty" : why);
      return false;
    }
    if (c["args"] && !ReadTextList(c["args"], &spec.args, &why)) {
      *error = AtKey(path, c, "args") + where + "args: " + why;
      return false;
    }
    if (!KnownPlaceholders(c, "args", path, where, error)) return false;
    s->controllers.push_back(spec);
  }
  return true;
}

// checks: a non-empty list, each entry against the table of check types (check_keys.h)
bool ReadChecks(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const YAML::Node list = root["checks"];
  const std::string help = ": a scenario must check something (e.g. - {type: not_fallen}; the "
                           "types are in docs/scenarios.md)";
  if (!list) {
    *error = "scenario '" + path + "': 'checks' is missing" + help;
    return false;
  }
  if (!list.IsSequence()) {
    *error = AtKey(path, root, "checks") + "'checks' must be a list" + help;
    return false;
  }
  if (list.size() == 0) {
    *error = AtKey(path, root, "checks") + "'checks' is empty" + help;
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    CheckSpec spec;
    if (!ParseCheck(list[i], i, s->duration, path, &spec, error)) return false;
    spec.line = list[i].Mark().line + 1;
    s->checks.push_back(spec);
  }
  return true;
}

}  // namespace

double CheckSpec::Number(const std::string& key, double fallback) const {
  auto it = params.find(key);
  return it == params.end() ? fallback : std::stod(it->second);
}

double CheckSpec::Number(const std::string& key) const {
  return Has(key) ? Number(key, 0) : CheckDefault(type, key);
}

namespace {

// the scenario in `root`, read from `path` (named in messages)
bool ReadScenario(const YAML::Node& root, const std::string& path, Scenario* out,
                  std::string* error) {
  if (!root.IsMap()) {
    *error = "scenario '" + path + "' is " + (root.IsNull() ? "empty" : "not a YAML mapping") +
             " (see docs/scenarios.md)";
    return false;
  }
  Scenario s;
  s.file = path;
  if (!KnownKeysOnly(root, kTopKeys, path, "", error)) return false;
  for (const auto& kv : root) s.lines[kv.first.Scalar()] = kv.first.Mark().line + 1;
  if (!root["name"]) {
    // the file's name without .yaml
    const auto slash = path.find_last_of('/');
    s.name = path.substr(slash == std::string::npos ? 0 : slash + 1);
    if (s.name.size() > 5 && s.name.substr(s.name.size() - 5) == ".yaml") s.name.resize(s.name.size() - 5);
  }
  if (!ReadRun(root, path, &s, error)) return false;
  if (root["contact_params"] && !ReadContactParams(root, path, &s, error)) return false;
  if (root["joint_params"] && !ReadJointParams(root, path, &s, error)) return false;
  if (root["effects"] && !ReadEffects(root, path, &s, error)) return false;
  if (root["pushes"]) {
    if (!ParsePushes(root["pushes"], path, &s.pushes, error)) return false;
    for (size_t i = 0; i < s.pushes.size(); ++i) {
      if (s.pushes[i].at + s.pushes[i].duration > s.duration) {
        *error = At(path, root["pushes"][i]) + "pushes[" + std::to_string(i) +
                 "]: the push ends after the run ('duration' " + std::to_string(s.duration) + " s)";
        return false;
      }
    }
  }
  if (!ReadControllers(root, path, &s, error) || !ReadChecks(root, path, &s, error)) return false;
  *out = s;
  return true;
}

}  // namespace

bool LoadScenario(const std::string& path, Scenario* out, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = "cannot read scenario '" + path + "': " + e.what();
    return false;
  }
  return ReadScenario(root, path, out, error);
}

bool ParseScenario(const std::string& text, const std::string& path, Scenario* out,
                   std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    *error = "cannot read scenario '" + path + "': " + e.what();
    return false;
  }
  return ReadScenario(root, path, out, error);
}

}  // namespace ohrp::runner
