// The scenario key `pushes` (see pushes.h and docs/scenarios.md).
#include "pushes.h"

#include <cmath>
#include <cstdio>
#include <set>

#include "sim_host/pushes.h"
#include "yaml_read.h"

namespace ohrp::runner {
namespace {

const std::set<std::string> kPushKeys = {"at", "duration", "direction", "impulse", "force"};

// "scenario 'FILE': line N: pushes[i]: "
std::string Where(const std::string& path, const YAML::Node& n, size_t i) {
  return "scenario '" + path + "': line " + std::to_string(n.Mark().line + 1) + ": pushes[" +
         std::to_string(i) + "]: ";
}

// a finite number under `key`; false with the error set when absent (and required) or bad
bool Number(const YAML::Node& push, const char* key, bool required, double* out,
            const std::string& where, std::string* error) {
  const YAML::Node n = push[key];
  if (!n) {
    if (required) *error = where + "'" + key + "' is required";
    return !required;
  }
  try {
    *out = n.as<double>();
  } catch (const YAML::Exception&) {
    *error = where + "'" + key + "' must be a number";
    return false;
  }
  if (!std::isfinite(*out)) {
    *error = where + "'" + key + "' must be finite";
    return false;
  }
  return true;
}

}  // namespace

void PushSpec::Force(double f_W[3]) const {
  if (explicit_force) {
    for (int k = 0; k < 3; ++k) f_W[k] = force[k];
    return;
  }
  const double a = direction_deg * M_PI / 180, f = impulse / duration;
  f_W[0] = f * std::cos(a);
  f_W[1] = f * std::sin(a);
  f_W[2] = 0;
}

std::string PushArgument(const PushSpec& p) {
  // the one representation of a push (sim_host/pushes.h): a window and a wrench on the base
  sim::Perturbation window;
  window.t0 = p.at;
  window.t1 = p.at + p.duration;
  p.Force(window.force);
  return sim::PerturbationText(window);
}

bool ParsePushes(const YAML::Node& list, const std::string& path, std::vector<PushSpec>* out,
                 std::string* error) {
  if (!list.IsSequence()) {
    *error = "scenario '" + path + "': line " + std::to_string(list.Mark().line + 1) +
             ": 'pushes' must be a list of {at, duration, direction, impulse} or {at, duration, force}";
    return false;
  }
  out->clear();
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node push = list[i];
    const std::string where = Where(path, push, i);
    if (!push.IsMap()) {
      *error = where + "each push must be a mapping, e.g. {at: 2.0, direction: 90, impulse: 15}";
      return false;
    }
    if (!KnownKeysOnly(push, kPushKeys, path, "pushes[" + std::to_string(i) + "]: ", error)) return false;
    PushSpec p;
    if (!Number(push, "at", true, &p.at, where, error) ||
        !Number(push, "duration", false, &p.duration, where, error))
      return false;
    if (p.at < 0) {
      *error = where + "'at' must be >= 0 s";
      return false;
    }
    if (!(p.duration > 0)) {
      *error = where + "'duration' must be > 0 s";
      return false;
    }
    if (push["force"]) {
      // an explicit world-frame force
      if (push["direction"] || push["impulse"]) {
        *error = where + "give either 'force' or 'direction' and 'impulse', not both";
        return false;
      }
      const YAML::Node f = push["force"];
      if (!f.IsSequence() || f.size() != 3) {
        *error = where + "'force' must be a list of 3 numbers [fx, fy, fz] in N, world frame";
        return false;
      }
      for (int k = 0; k < 3; ++k) {
        try {
          p.force[k] = f[k].as<double>();
        } catch (const YAML::Exception&) {
          *error = where + "'force' must be a list of 3 numbers [fx, fy, fz] in N, world frame";
          return false;
        }
        if (!std::isfinite(p.force[k])) {
          *error = where + "'force' must be finite";
          return false;
        }
      }
      p.explicit_force = true;
    } else {
      // a horizontal direction and an impulse
      if (!Number(push, "direction", true, &p.direction_deg, where, error) ||
          !Number(push, "impulse", true, &p.impulse, where, error))
        return false;
      if (p.impulse < 0) {
        *error = where + "'impulse' must be >= 0 N s (turn 'direction' to push the other way)";
        return false;
      }
    }
    out->push_back(p);
  }
  return true;
}

}  // namespace ohrp::runner
