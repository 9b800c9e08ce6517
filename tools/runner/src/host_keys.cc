// The scenario keys that are sim_host options (see host_keys.h and cli/host_options.h).
#include "host_keys.h"

#include <cstdio>
#include <variant>

#include "cli/host_options.h"
#include "pushes.h"
#include "sim_host/effects.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

using cli::HostOption;
using cli::OptionType;

// a table key's field in Scenario (the keys without one are kept in Scenario::host_options)
using Field = std::variant<std::monostate, double*, int*, std::string*, bool*,
                           std::vector<std::string>*, std::vector<PushSpec>*>;

Field FieldOf(Scenario* s, const std::string& key) {
  if (key == "duration") return &s->duration;
  if (key == "on_controller_loss") return &s->on_controller_loss;
  if (key == "controller_timeout") return &s->controller_timeout;
  if (key == "log_every") return &s->log_every;
  if (key == "control_period") return &s->control_period;
  if (key == "physics_dt") return &s->physics_dt;
  if (key == "integrator") return &s->integrator;
  if (key == "camera_rate") return &s->camera_rate;
  if (key == "keyframe") return &s->keyframe;
  if (key == "realtime") return &s->realtime;
  if (key == "contact") return &s->contact;
  if (key == "on_fall") return &s->on_fall;
  if (key == "fall_allow_contact") return &s->fall_allow_contact;
  if (key == "pushes") return &s->pushes;
  return std::monostate{};  // effects (Scenario::effects is the mapping; the option's text here)
}

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

// effects: NAME: on|off, contact:BODY1/BODY2: on|off, noise.KIND: STD, noise.seed: N, each
// checked by sim_host's own parser (docs/effects.md), in the file's order
bool ReadEffects(const YAML::Node& n, const std::string& path, Scenario* s, std::string* text,
                 std::string* why) {
  if (!n.IsMap()) {
    *why = "'effects' must be a mapping, e.g. {noise: on, gravity: off}";
    return false;
  }
  for (const auto& kv : n) {
    std::string key, value;
    const std::string at = At(path, kv.first);
    if (!ReadText(kv.first, &key, why) || !ReadText(kv.second, &value, why)) {
      *why = "\n" + at + "effects: each entry must be NAME: on, off or a number";
      return false;
    }
    if (key.find_first_of(",=") != std::string::npos || value.find_first_of(",=") != std::string::npos) {
      *why = "\n" + at + "effects: '" + key + "' has a ',' or '='";
      return false;
    }
    sim::EffectRequests requests;
    if (!sim::ParseEffectRequests(key + "=" + value, &requests, why)) {
      *why = "\n" + at + *why;
      return false;
    }
    *text += (text->empty() ? "" : ",") + key + "=" + value;
  }
  return true;
}

// the value `n` of table entry `o` into `s`; false with `*why` (a why starting with '\n' carries
// its own place: an entry of a mapping or a list)
bool ReadOne(const HostOption& o, const YAML::Node& n, const std::string& path, Scenario* s,
             std::string* why) {
  Field field = FieldOf(s, o.key);
  std::string text;  // the option's value, for a key without a field
  switch (o.type) {
    case OptionType::kNumber: {
      double v = 0;
      if (std::holds_alternative<int*>(field)) {
        long long whole = 0;
        if (!ReadInteger(n, &whole, why)) return false;
        v = static_cast<double>(whole);
      } else if (!ReadNumber(n, &v, why)) {
        return false;
      }
      if (*why = cli::CheckHostNumber(o, v, n.Scalar()); !why->empty()) return false;
      if (auto* d = std::get_if<double*>(&field)) **d = v;
      else if (auto* i = std::get_if<int*>(&field)) **i = static_cast<int>(v);
      else text = Num(v);
      break;
    }
    case OptionType::kChoice:
      if (!ReadChoice(n, cli::HostOptionChoices(o), &text, why)) return false;
      break;
    case OptionType::kText:
      if (!ReadText(n, &text, why)) return false;
      if (text.empty()) {
        *why = "must not be empty";
        return false;
      }
      break;
    case OptionType::kFlag: {
      bool b = false;
      if (!ReadBool(n, &b, why)) return false;
      if (auto* f = std::get_if<bool*>(&field)) **f = b;
      else text = b ? "true" : "false";
      break;
    }
    case OptionType::kList: {
      std::vector<std::string> list;
      if (!ReadTextList(n, &list, why)) return false;
      if (auto* l = std::get_if<std::vector<std::string>*>(&field)) { **l = list; return true; }
      for (const auto& b : list) text += (text.empty() ? "" : ",") + b;
      break;
    }
    case OptionType::kEffects:
      if (!ReadEffects(n, path, s, &text, why)) return false;
      break;
    case OptionType::kPushes:
      if (!ParsePushes(n, path, &s->pushes, why)) {
        *why = "\n" + *why;
        return false;
      }
      return true;
  }
  if (auto* t = std::get_if<std::string*>(&field)) **t = text;
  else if (!text.empty()) s->host_options[o.key] = text;
  return true;
}

// the option values of entry `o` for `s` (several for pushes; none when unset)
std::vector<std::string> Values(const HostOption& o, const Scenario& s) {
  Scenario copy = s;
  const Field field = FieldOf(&copy, o.key);
  std::string text;
  if (auto* d = std::get_if<double*>(&field)) text = Num(**d);
  else if (auto* i = std::get_if<int*>(&field)) text = std::to_string(**i);
  else if (auto* t = std::get_if<std::string*>(&field)) text = **t;
  else if (auto* b = std::get_if<bool*>(&field)) text = **b ? "true" : "false";
  else if (auto* l = std::get_if<std::vector<std::string>*>(&field))
    for (const auto& w : **l) text += (text.empty() ? "" : ",") + w;
  else if (auto* p = std::get_if<std::vector<PushSpec>*>(&field)) {
    std::vector<std::string> pushes;
    for (const auto& push : **p) pushes.push_back(PushArgument(push));
    return pushes;
  } else if (auto it = s.host_options.find(o.key); it != s.host_options.end()) {
    text = it->second;
  }
  if (text.empty() || text == o.left_out) return {};
  return {text};
}

}  // namespace

bool ReadHostKeys(const YAML::Node& root, const std::string& path, Scenario* s, std::string* error) {
  for (const HostOption& o : cli::kHostOptions) {
    const YAML::Node n = root[o.key];
    if (!n) continue;
    std::string why;
    if (ReadOne(o, n, path, s, &why)) continue;
    // a place of its own (an entry of the mapping or list), or the key's
    *error = why[0] == '\n' ? why.substr(1) : AtKey(path, root, o.key) + o.key + ": " + why;
    return false;
  }
  return true;
}

void AppendHostOptions(const Scenario& s, std::vector<std::string>* argv) {
  for (const HostOption& o : cli::kHostOptions) {
    for (const std::string& v : Values(o, s)) {
      argv->push_back(o.option);
      if (o.type != OptionType::kFlag) argv->push_back(v);
    }
  }
}

}  // namespace ohrp::runner
