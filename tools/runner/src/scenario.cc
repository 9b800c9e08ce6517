// Scenario parsing (see scenario.h): every key and value is checked here, before anything runs.
#include "runner/scenario.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "check_parse.h"
#include "cli/host_options.h"
#include "host_keys.h"
#include "runner/check_keys.h"
#include "runner/commands.h"
#include "scenario_params.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

// the runner's own keys; the keys that are sim_host options are in cli/host_options.h
const std::set<std::string> kRunnerKeys = {
    "name", "description", "scene", "wall_timeout", "sim_args", "controllers", "checks",
    "plot_joints", "plot_torques", "contact_params", "joint_params", "expect_fall"};

// every top-level key: the runner's and the table's
std::set<std::string> TopKeys() {
  std::set<std::string> keys = kRunnerKeys;
  for (const cli::HostOption& o : cli::kHostOptions) keys.insert(o.key);
  return keys;
}
const std::set<std::string> kControllerKeys = {"program", "args"};

// bounds of the runner's own numbers (sim_host's: cli/host_options.h)
constexpr double kMaxWallTimeout = 1e6;      // [s] wall

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

// the runner's scalar keys, then the sim_host options (cli/host_options.h), each in its range
bool ReadRun(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  const bool ok =
      Optional(root, "name", path, error, NonEmptyText(&s->name)) &&
      Optional(root, "description", path, error,
               [&](const YAML::Node& n, std::string* why) { return ReadText(n, &s->description, why); }) &&
      Optional(root, "scene", path, error, NonEmptyText(&s->scene)) &&
      Optional(root, "wall_timeout", path, error,
               NumberIn(&s->wall_timeout, 0, kMaxWallTimeout, false, "s (0: derived)")) &&
      Optional(root, "sim_args", path, error, TextList(&s->sim_args)) &&
      Optional(root, "plot_joints", path, error, TextList(&s->plot_joints)) &&
      Optional(root, "plot_torques", path, error, TextList(&s->plot_torques)) &&
      Optional(root, "expect_fall", path, error,
               [&](const YAML::Node& n, std::string* why) { return ReadBool(n, &s->expect_fall, why); }) &&
      KnownPlaceholders(root, "sim_args", path, "", error) &&
      ReadHostKeys(root, path, s, error);
  if (!ok) return false;

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
  if (!KnownKeysOnly(root, TopKeys(), path, "", error)) return false;
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
  if (root["pushes"]) {
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
