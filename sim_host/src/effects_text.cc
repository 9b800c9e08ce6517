// The text of `sim_host --explain` and of a run's start (EffectsPlan::Table, Short).
#include <cstdio>
#include <string>

#include "effects_internal.h"

namespace ohrp::sim {

using effects_internal::kNames;

std::string EffectsPlan::Table() const {
  std::string out = "effect             state  why\n";
  char line[64];
  for (int i = 0; i < kEffectCount; ++i) {
    std::snprintf(line, sizeof(line), "%-18s %-5s  ", kNames[i], effects[i].on ? "on" : "off");
    out += line + effects[i].reason + "\n";
  }
  if (!pairs.empty()) {
    out += "contact pairs (MuJoCo's native contact, contact:BODY1/BODY2):\n";
    for (const auto& cp : pairs) {
      std::snprintf(line, sizeof(line), "  %-32s %-5s  ", cp.name.c_str(), cp.on ? "on" : "off");
      out += line + cp.reason + "\n";
    }
  }
  char noise[256];
  if (on(Effect::kNoise)) {
    std::snprintf(noise, sizeof(noise),
                  "noise std: q %g rad, dq %g rad/s, tau %g N m, force %g N, torque %g N m, gyro "
                  "%g rad/s, accel %g m/s^2, orientation %g rad; seed %llu\n",
                  this->noise.q, this->noise.dq, this->noise.tau, this->noise.force,
                  this->noise.torque, this->noise.gyro, this->noise.accel,
                  this->noise.orientation, static_cast<unsigned long long>(this->noise.seed));
    out += noise;
  }
  return out;
}

std::string EffectsPlan::Short() const {
  std::string on_list, off_list;
  for (int i = 0; i < kEffectCount; ++i) {
    std::string& l = effects[i].on ? on_list : off_list;
    l += (l.empty() ? "" : ", ") + std::string(kNames[i]);
  }
  return "effects on: " + on_list + "\neffects off: " + off_list + " (sim_host --explain says why)";
}

}  // namespace ohrp::sim
