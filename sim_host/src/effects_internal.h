// Internal to sim_host's effects module (effects.cc and its siblings, effects.h): the names
// table, the scene queries the resolution and the contact filter share (MuJoCo's own collision
// rules, the soles, the sensors' kinds) and the scene's defaults.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

#include "sim_host/effects.h"

namespace ohrp::sim::effects_internal {

// the names of --effects and docs/effects.md, by Effect
extern const char* const kNames[kEffectCount];

inline int I(Effect e) { return static_cast<int>(e); }

// names of bodies and geoms (a made-up one when the model has none)
std::string BodyName(const mjModel* m, int b);
std::string GeomName(const mjModel* m, int g);
// "a, b, c, ... (N)": at most `max` items
std::string Join(const std::vector<std::string>& v, size_t max = 6);

// the sole geoms as SetUpFeet finds them: named, or every "*_SOLE" geom
std::vector<int> Soles(const mjModel* m, const FeetOptions& feet);

// MuJoCo 2.2.2's own rules: contype/conaffinity, and the parent-child filter
bool BitmaskAllows(const mjModel* m, int g1, int g2);
bool ParentFiltered(const mjModel* m, int b1, int b2);

// the body pairs of the scene whose geoms MuJoCo's contact can make touch
std::vector<ContactPair> CandidatePairs(const mjModel* m, const std::vector<int>& soles);

enum class SensorKind { kForceTorque, kGyro, kAccel, kOrientation, kOther };
// which effect reads MuJoCo sensor `s`
SensorKind KindOf(const mjModel* m, const model::RobotMap& robot, int s);
bool KindOn(const EffectsPlan& p, SensorKind k);

// Step 1 of the resolution: every effect as the scene (and the contact choice, the log)
// declares it, with its reason (effects_defaults.cc); fills `p->effects` and `p->pairs`.
// Returns whether the soles are on the soft-foot contact.
bool DeclareDefaults(const mjModel* m, const model::RobotMap& robot, const FeetOptions& feet, bool log,
                     EffectsPlan* p);

}  // namespace ohrp::sim::effects_internal
