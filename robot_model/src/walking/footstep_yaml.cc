// The YAML reader of footstep files (see walking/footstep_file.h and footstep_rows.h).
#include <yaml-cpp/yaml.h>

#include "footstep_rows.h"

namespace ohrp::walking {
namespace {

// a node's first line (1-based)
int LineOf(const YAML::Node& n) { return n.Mark().line + 1; }

// a key's text ("?" for a key that is not a scalar)
std::string KeyText(const YAML::Node& k) { return k.IsScalar() ? k.Scalar() : "?"; }

// a YAML scalar's text, or why it is not one
bool Scalar(const YAML::Node& n, const std::string& key, std::string* out, std::string* why) {
  if (n.IsScalar()) {
    *out = n.Scalar();
    return true;
  }
  const char* what = n.IsSequence() ? "a list" : n.IsMap() ? "a mapping" : "empty";
  *why = key + ": must be a single value, not " + what;
  return false;
}

// `defaults:`: height and duration
bool ReadDefaults(const YAML::Node& map, const std::string& name, int line, Header* h,
                  std::string* error) {
  if (!map.IsMap())
    return Fail(error, At(name, line), "defaults: must be a mapping of height and duration");
  std::string v, why;
  for (const auto& d : map) {
    const std::string key = KeyText(d.first);
    const std::string at = At(name, LineOf(d.first));
    double x;
    if (key != "height" && key != "duration")
      return Fail(error, at, "defaults: unknown key '" + key + "' (known: duration, height)");
    if (!Scalar(d.second, key, &v, &why)) return Fail(error, at, why);
    if (!Number(v, &x)) return Fail(error, at, key + ": must be a finite number, not '" + v + "'");
    why = key == "height" ? CheckHeight(x) : CheckDuration(x);
    if (!why.empty()) return Fail(error, at, why);
    (key == "height" ? h->height : h->duration) = x;
  }
  return true;
}

// one item of `steps:`
bool ReadStep(const YAML::Node& item, const std::string& name, Written* w, std::string* error) {
  w->line = LineOf(item);
  if (!item.IsMap())
    return Fail(error, At(name, w->line),
                "steps: each step must be a mapping, e.g. {foot: left, x: 0.2, y: 0.09, "
                "yaw_deg: 0}");
  std::set<std::string> keys;
  std::string v, why;
  for (const auto& kv : item) {
    const std::string key = KeyText(kv.first);
    const std::string at = At(name, LineOf(kv.first));
    if (!StepKeys().count(key))
      return Fail(error, at, "unknown key '" + key + "' (known: " + kStepKeys + ")");
    if (!keys.insert(key).second) return Fail(error, at, key + ": given twice");
    if (!Scalar(kv.second, key, &v, &why)) return Fail(error, at, why);
    why = SetValue(key, v, w);
    if (!why.empty()) return Fail(error, at, why);
    if (key == "foot") w->foot_line = LineOf(kv.first);
  }
  why = Missing(keys);
  return why.empty() || Fail(error, At(name, w->line), why);
}

}  // namespace

bool ParseYamlSteps(const std::string& text, const std::string& name, Header* h,
                    std::vector<Written>* rows, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return Fail(error, At(name, e.mark.line + 1), "not valid YAML: " + e.msg);
  }
  if (!root.IsMap())
    return Fail(error, At(name, 1),
                "steps: the file must be a mapping with a list `steps:` (docs/footsteps.md)");
  // the top level: frame, defaults, steps, description
  std::set<std::string> seen;
  YAML::Node steps;
  int steps_line = 0;  // 0: no steps
  std::string v, why;
  for (const auto& kv : root) {
    const std::string key = KeyText(kv.first);
    const int line = LineOf(kv.first);
    const std::string at = At(name, line);
    if (!seen.insert(key).second) return Fail(error, at, key + ": given twice");
    if (key == "frame") {
      if (!Scalar(kv.second, key, &v, &why)) return Fail(error, at, why);
      if (v != "start" && v != "world")
        return Fail(error, at, "frame: must be start or world, not '" + v + "'");
      h->world = v == "world";
    } else if (key == "defaults") {
      if (!ReadDefaults(kv.second, name, line, h, error)) return false;
    } else if (key == "steps") {
      steps = kv.second;
      steps_line = line;
    } else if (key == "description") {
      if (!Scalar(kv.second, key, &v, &why)) return Fail(error, at, why);
    } else {
      return Fail(error, at,
                  "unknown key '" + key + "' (known: defaults, description, frame, steps)");
    }
  }
  if (steps_line == 0)
    return Fail(error, At(name, 1),
                "steps: missing: the file needs a list `steps:` (docs/footsteps.md)");
  if (!steps.IsSequence())
    return Fail(error, At(name, steps_line),
                "steps: must be a list of steps, e.g. - {foot: left, x: 0.2, y: 0.09, yaw_deg: 0}");
  // the steps
  for (const auto& item : steps) {
    Written w;
    if (!ReadStep(item, name, &w, error)) return false;
    rows->push_back(w);
  }
  return true;
}

}  // namespace ohrp::walking
