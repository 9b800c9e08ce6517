// The effects' names and the syntax of `sim_host --effects` (effects.h).
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "effects_internal.h"

namespace ohrp::sim {
namespace effects_internal {

const char* const kNames[kEffectCount] = {
    "gravity",        "joint_limits", "passive",      "native_contact", "self_contact",
    "self_collision",
    "soft_contact",   "encoders",     "joint_velocities", "joint_torques", "force_torque",
    "gyro",           "accelerometer", "orientation", "rne_post",       "other_sensors",
    "noise",          "cameras",      "log",          "log_base",       "log_joints",
    "log_force_torque", "log_imu"};

}  // namespace effects_internal

using effects_internal::I;
using effects_internal::kNames;

const char* EffectName(Effect e) {
  const int i = I(e);
  return i >= 0 && i < kEffectCount ? kNames[i] : "?";
}

bool ParseEffectName(const std::string& name, Effect* e) {
  for (int i = 0; i < kEffectCount; ++i) {
    if (name == kNames[i]) {
      *e = static_cast<Effect>(i);
      return true;
    }
  }
  return false;
}

bool ParseEffectRequests(const std::string& spec, EffectRequests* out, std::string* error) {
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) {
      *error = "effects: '" + item + "' is not NAME=VALUE (e.g. gravity=off, noise=on, noise.force=2)";
      return false;
    }
    const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    if (key.rfind("noise.", 0) == 0) {
      const std::string kind = key.substr(6);
      char* end = nullptr;
      if (kind == "seed") {
        const unsigned long long seed = std::strtoull(value.c_str(), &end, 10);
        if (*end || value[0] == '-') {
          *error = "effects: noise.seed must be a non-negative integer, not '" + value + "'";
          return false;
        }
        out->noise.seed = seed;
        continue;
      }
      const double v = std::strtod(value.c_str(), &end);
      if (*end || !std::isfinite(v) || v < 0) {
        *error = "effects: " + key + " must be a standard deviation >= 0 (SI units), not '" + value + "'";
        return false;
      }
      NoiseOptions& n = out->noise;
      double* field = kind == "q" ? &n.q : kind == "dq" ? &n.dq : kind == "tau" ? &n.tau
                      : kind == "force" ? &n.force : kind == "torque" ? &n.torque
                      : kind == "gyro" ? &n.gyro : kind == "accel" ? &n.accel
                      : kind == "orientation" ? &n.orientation : nullptr;
      if (!field) {
        *error = "effects: unknown noise kind '" + kind +
                 "' (q, dq, tau, force, torque, gyro, accel, orientation, seed)";
        return false;
      }
      *field = v;
      continue;
    }
    int8_t state;
    if (value == "on" || value == "true" || value == "1") state = 1;
    else if (value == "off" || value == "false" || value == "0") state = 0;
    else {
      *error = "effects: '" + key + "' must be on or off, not '" + value + "'";
      return false;
    }
    if (key.rfind("contact:", 0) == 0) {
      const std::string bodies = key.substr(8);
      const auto slash = bodies.find('/');
      if (slash == std::string::npos || slash == 0 || slash + 1 == bodies.size()) {
        *error = "effects: '" + key + "' must name two bodies, contact:BODY1/BODY2";
        return false;
      }
      out->pairs.push_back({bodies.substr(0, slash), bodies.substr(slash + 1), state == 1});
      continue;
    }
    Effect e;
    if (!ParseEffectName(key, &e)) {
      std::string known;
      for (int i = 0; i < kEffectCount; ++i) {
        if (i) known += ' ';
        known += kNames[i];
      }
      *error = "effects: unknown effect '" + key + "' (known: " + known +
               ", contact:BODY1/BODY2, noise.KIND)";
      return false;
    }
    out->request[I(e)] = state;
  }
  return true;
}

}  // namespace ohrp::sim
