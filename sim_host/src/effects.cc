// Effects resolution (see effects.h and docs/effects.md): the scene's defaults
// (effects_defaults.cc), then the requests, the dependencies to a fixed point and the contact
// pairs.
#include "sim_host/effects.h"

#include <string>
#include <vector>

#include "effects_internal.h"

namespace ohrp::sim {
namespace {

using namespace effects_internal;

// what each effect needs to be computed
std::vector<Effect> Needs(Effect e) {
  switch (e) {
    case Effect::kSelfContact: return {Effect::kNativeContact};
    case Effect::kForceTorque: return {Effect::kRnePost};
    case Effect::kAccelerometer: return {Effect::kRnePost};
    case Effect::kLogBase: return {Effect::kLog};
    case Effect::kLogJoints: return {Effect::kLog, Effect::kEncoders, Effect::kJointTorques};
    case Effect::kLogForceTorque: return {Effect::kLog, Effect::kForceTorque};
    case Effect::kLogImu:
      return {Effect::kLog, Effect::kGyro, Effect::kAccelerometer, Effect::kOrientation};
    default: return {};
  }
}

}  // namespace

bool ResolveEffects(const mjModel* m, const model::RobotMap& robot, const FeetOptions& feet, bool log,
                    const EffectRequests& req, EffectsPlan* plan, std::string* error) {
  EffectsPlan p;
  p.noise = req.noise;
  auto& E = p.effects;
  const bool soft = DeclareDefaults(m, robot, feet, log, &p);

  // requests
  for (int i = 0; i < kEffectCount; ++i) {
    const int8_t r = req.request[i];
    if (r < 0) continue;
    const Effect e = static_cast<Effect>(i);
    if (e == Effect::kSoftContact && (r == 1) != soft) {
      *error = std::string("soft_contact=") + (r ? "on" : "off") +
               ": the contact under the soles is chosen with --contact (scenario key 'contact')";
      return false;
    }
    if (r == 1 && !E[i].declared) {
      *error = std::string(kNames[i]) + "=on: cannot be switched on: " + E[i].reason;
      return false;
    }
    E[i].on = r == 1;
    E[i].reason = std::string(r ? "switched on" : "switched off") + " by request";
  }

  // dependencies, to a fixed point
  std::array<bool, kEffectCount> by_need{};  // switched on by a dependency
  std::array<bool, kEffectCount> blocked{};  // off for good: requested off, or a need is
  for (int i = 0; i < kEffectCount; ++i) blocked[i] = req.request[i] == 0 || !E[i].declared;
  for (bool changed = true; changed;) {
    changed = false;
    for (int i = 0; i < kEffectCount; ++i) {
      if (!E[i].on) continue;
      for (Effect need : Needs(static_cast<Effect>(i))) {
        EffectState& y = E[I(need)];
        if (y.on) continue;
        if (!blocked[I(need)]) {
          y.on = true;
          by_need[I(need)] = true;
          changed = true;
          continue;
        }
        if (req.request[i] == 1) {
          *error = std::string(kNames[i]) + "=on needs " + EffectName(need) + ", which is off (" +
                   y.reason + ")";  // conflicting requests, or the scene lacks it
          return false;
        }
        E[i].on = false;
        blocked[i] = true;
        E[i].reason = std::string("needs ") + EffectName(need) + ", which is off";
        changed = true;
        break;
      }
    }
  }
  // "needed by" for what the dependencies switched on or keep on
  for (int y = 0; y < kEffectCount; ++y) {
    if (!E[y].on) continue;
    std::vector<std::string> by;
    for (int x = 0; x < kEffectCount; ++x) {
      if (!E[x].on) continue;
      for (Effect need : Needs(static_cast<Effect>(x)))
        if (I(need) == y) by.push_back(kNames[x]);
    }
    if (by.empty()) {
      if (by_need[y]) {  // switched on for an effect that went off later
        E[y].on = false;
        E[y].reason = "nothing that is on needs it";
      }
      continue;
    }
    if (by_need[y]) E[y].reason = "needed by " + Join(by, 20);
    else E[y].reason += "; needed by " + Join(by, 20);
  }

  // contact pairs
  for (const auto& r : req.pairs) {
    const int b1 = r.body1 == "world" ? 0 : mj_name2id(m, mjOBJ_BODY, r.body1.c_str());
    const int b2 = r.body2 == "world" ? 0 : mj_name2id(m, mjOBJ_BODY, r.body2.c_str());
    bool found = false;
    for (auto& cp : p.pairs) {
      if (!((cp.body1 == b1 && cp.body2 == b2) || (cp.body1 == b2 && cp.body2 == b1))) continue;
      found = true;
      if (r.on && cp.soles && soft) {
        *error = "contact:" + r.body1 + "/" + r.body2 + "=on: the sole is on the soft-foot contact (use --contact native)";
        return false;
      }
      if (r.on && !p.on(Effect::kNativeContact)) {
        *error = "contact:" + r.body1 + "/" + r.body2 + "=on needs native_contact, which is off";
        return false;
      }
    }
    if (!found || b1 < 0 || b2 < 0) {
      std::vector<std::string> names;
      for (const auto& cp : p.pairs) names.push_back(cp.name);
      *error = "contact:" + r.body1 + "/" + r.body2 + ": the scene has no such colliding body pair (" +
               (names.empty() ? std::string("it has none") : "it has " + Join(names, 12)) + ")";
      return false;
    }
  }
  int pairs_on = 0;
  for (auto& cp : p.pairs) {
    int8_t r = -1;
    for (const auto& q : req.pairs) {
      const int b1 = q.body1 == "world" ? 0 : mj_name2id(m, mjOBJ_BODY, q.body1.c_str());
      const int b2 = q.body2 == "world" ? 0 : mj_name2id(m, mjOBJ_BODY, q.body2.c_str());
      if ((cp.body1 == b1 && cp.body2 == b2) || (cp.body1 == b2 && cp.body2 == b1)) r = q.on;
    }
    const std::string n = std::to_string(cp.geom_pairs) + " geom pair" + (cp.geom_pairs > 1 ? "s" : "");
    if (cp.soles && soft) {
      cp.on = false;
      cp.reason = "a sole is on the soft-foot contact (MuJoCo's contact is off for it)";
    } else if (!p.on(Effect::kNativeContact)) {
      cp.on = false;
      cp.reason = "native_contact is off";
    } else if (r >= 0) {
      cp.on = r == 1;
      cp.reason = std::string(r ? "switched on" : "switched off") + " by request (" + n + ")";
    } else if (cp.self && !p.on(Effect::kSelfContact)) {
      cp.on = false;
      cp.reason = "self_contact is off";
    } else {
      cp.on = true;
      cp.reason = "the scene lets them collide (" + n + ")";
    }
    pairs_on += cp.on;
  }
  if (p.on(Effect::kNativeContact) && pairs_on == 0) {
    E[I(Effect::kNativeContact)].on = false;
    E[I(Effect::kNativeContact)].reason = "every body pair is switched off";
  }
  *plan = std::move(p);
  return true;
}

}  // namespace ohrp::sim
