// Scenario parsing (see scenario.h).
#include "runner/scenario.h"

#include <yaml-cpp/yaml.h>

#include <set>

#include "pushes.h"

namespace ohrp::runner {
namespace {

const std::set<std::string> kTopKeys = {
    "name", "description", "scene", "keyframe", "duration", "physics_dt", "control_period",
    "integrator", "realtime", "on_controller_loss", "controller_timeout", "wall_timeout",
    "log_every", "sim_args", "controllers", "checks", "plot_joints", "plot_torques", "contact",
    "contact_params", "effects", "pushes"};

const std::set<std::string> kContactParams = {"stiffness", "exponent", "damping", "friction",
                                              "tangential_stiffness", "tangential_damping"};

template <typename T>
bool Get(const YAML::Node& n, const char* key, T* out, std::string* error) {
  if (!n[key]) return true;
  try {
    *out = n[key].as<T>();
    return true;
  } catch (const YAML::Exception& e) {
    *error = std::string("key '") + key + "': " + e.what();
    return false;
  }
}

}  // namespace

double CheckSpec::Number(const std::string& key, double fallback) const {
  auto it = params.find(key);
  return it == params.end() ? fallback : std::stod(it->second);
}

bool LoadScenario(const std::string& path, Scenario* out, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = "cannot read scenario '" + path + "': " + e.what();
    return false;
  }
  if (!root.IsMap()) {
    *error = "scenario '" + path + "' is not a YAML mapping (see docs/scenarios.md)";
    return false;
  }
  Scenario s;
  s.file = path;
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (!kTopKeys.count(key)) {
      *error = "scenario '" + path + "': unknown key '" + key + "' (see docs/scenarios.md)";
      return false;
    }
  }
  std::string e;
  bool ok = Get(root, "name", &s.name, &e) && Get(root, "description", &s.description, &e) &&
            Get(root, "scene", &s.scene, &e) && Get(root, "keyframe", &s.keyframe, &e) &&
            Get(root, "duration", &s.duration, &e) && Get(root, "physics_dt", &s.physics_dt, &e) &&
            Get(root, "control_period", &s.control_period, &e) &&
            Get(root, "integrator", &s.integrator, &e) && Get(root, "realtime", &s.realtime, &e) &&
            Get(root, "on_controller_loss", &s.on_controller_loss, &e) &&
            Get(root, "controller_timeout", &s.controller_timeout, &e) &&
            Get(root, "wall_timeout", &s.wall_timeout, &e) &&
            Get(root, "log_every", &s.log_every, &e) && Get(root, "sim_args", &s.sim_args, &e) &&
            Get(root, "plot_joints", &s.plot_joints, &e) &&
            Get(root, "plot_torques", &s.plot_torques, &e) && Get(root, "contact", &s.contact, &e) &&
            Get(root, "contact_params", &s.contact_params, &e);
  if (!ok) {
    *error = "scenario '" + path + "': " + e;
    return false;
  }
  if (s.scene.empty()) {
    *error = "scenario '" + path + "': 'scene' is required (an MJCF file, e.g. mjcf/hrp1s/scene_flat.xml)";
    return false;
  }
  if (s.name.empty()) {
    const auto slash = path.find_last_of('/');
    s.name = path.substr(slash == std::string::npos ? 0 : slash + 1);
    if (s.name.size() > 5 && s.name.substr(s.name.size() - 5) == ".yaml") s.name.resize(s.name.size() - 5);
  }
  if (!(s.duration > 0)) {
    *error = "scenario '" + path + "': 'duration' must be > 0 simulated seconds";
    return false;
  }
  if (!s.contact.empty() && s.contact != "soft" && s.contact != "native" && s.contact != "rigid") {
    *error = "scenario '" + path + "': 'contact' must be soft, native or rigid";
    return false;
  }
  for (const auto& kv : s.contact_params) {
    if (!kContactParams.count(kv.first)) {
      *error = "scenario '" + path + "': unknown contact parameter '" + kv.first +
               "' (known: stiffness, exponent, damping, friction, tangential_stiffness, "
               "tangential_damping)";
      return false;
    }
  }
  if (root["effects"]) {
    // NAME: on|off, contact:BODY1/BODY2: on|off, noise.KIND: STD, noise.seed: N; sim_host
    // checks the names and values (docs/effects.md) and refuses bad ones before running
    if (!root["effects"].IsMap()) {
      *error = "scenario '" + path + "': 'effects' must be a mapping, e.g. {noise: on, gravity: off}";
      return false;
    }
    std::string list;
    for (const auto& kv : root["effects"]) {
      if (!kv.second.IsScalar()) {
        *error = "scenario '" + path + "': effects: '" + kv.first.as<std::string>() +
                 "' must be on, off or a number";
        return false;
      }
      const std::string key = kv.first.as<std::string>(), value = kv.second.as<std::string>();
      if (key.find_first_of(",=") != std::string::npos || value.find_first_of(",=") != std::string::npos) {
        *error = "scenario '" + path + "': effects: '" + key + "' has a ',' or '='";
        return false;
      }
      s.effects[key] = value;
      list += (list.empty() ? "" : ",") + key + "=" + value;
    }
    if (!list.empty()) s.sim_args.insert(s.sim_args.begin(), {"--effects", list});
  }
  if (root["pushes"]) {
    if (!ParsePushes(root["pushes"], path, &s.pushes, error)) return false;
    for (size_t i = 0; i < s.pushes.size(); ++i) {
      if (s.pushes[i].at + s.pushes[i].duration > s.duration) {
        *error = "scenario '" + path + "': pushes[" + std::to_string(i) +
                 "]: the push ends after the run ('duration' " + std::to_string(s.duration) + " s)";
        return false;
      }
    }
  }
  if (s.on_controller_loss != "end" && s.on_controller_loss != "wait" &&
      s.on_controller_loss != "continue") {
    *error = "scenario '" + path + "': 'on_controller_loss' must be end, wait or continue";
    return false;
  }
  if (root["controllers"]) {
    if (!root["controllers"].IsSequence()) {
      *error = "scenario '" + path + "': 'controllers' must be a list of {program, args}";
      return false;
    }
    for (const auto& c : root["controllers"]) {
      ControllerSpec spec;
      if (!Get(c, "program", &spec.program, &e) || !Get(c, "args", &spec.args, &e) ||
          spec.program.empty()) {
        *error = "scenario '" + path + "': each controller needs 'program' (and optional 'args' list)" +
                 (e.empty() ? "" : ": " + e);
        return false;
      }
      s.controllers.push_back(spec);
    }
  }
  if (root["checks"]) {
    if (!root["checks"].IsSequence()) {
      *error = "scenario '" + path + "': 'checks' must be a list";
      return false;
    }
    for (const auto& c : root["checks"]) {
      CheckSpec spec;
      if (!c.IsMap() || !c["type"]) {
        *error = "scenario '" + path + "': each check needs a 'type'";
        return false;
      }
      for (const auto& kv : c) {
        const std::string key = kv.first.as<std::string>();
        if (key == "type") spec.type = kv.second.as<std::string>();
        else if (kv.second.IsScalar()) spec.params[key] = kv.second.as<std::string>();
        else if (kv.second.IsSequence()) {
          std::string joined;
          for (const auto& item : kv.second) joined += (joined.empty() ? "" : ",") + item.as<std::string>();
          spec.params[key] = joined;
        }
      }
      s.checks.push_back(spec);
    }
  }
  *out = s;
  return true;
}

}  // namespace ohrp::runner
