// Putting an effects plan into the mjModel (effects.h): disable flags, sensor stages, and the
// contact filter for switched-off pairs.
#include <cstdint>
#include <vector>

#include "effects_internal.h"

namespace ohrp::sim {
namespace {

using namespace effects_internal;

//---------------- contact filter for switched-off pairs ----------------

struct Filter {
  const mjModel* m = nullptr;
  int nbody = 0;
  std::vector<uint8_t> off;  // nbody x nbody: 1 when the body pair is switched off
} g_filter;

int ContactFilter(const mjModel* m, mjData*, int g1, int g2) {
  const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
  if (m == g_filter.m && g_filter.off[b1 * g_filter.nbody + b2]) return 1;
  // otherwise MuJoCo's own rules, which a user filter replaces
  return !BitmaskAllows(m, g1, g2) || ParentFiltered(m, b1, b2);
}

}  // namespace

void ApplyEffects(const EffectsPlan& plan, const model::RobotMap& robot, mjModel* m) {
  if (!plan.on(Effect::kGravity)) m->opt.disableflags |= mjDSBL_GRAVITY;
  if (!plan.on(Effect::kJointLimits)) m->opt.disableflags |= mjDSBL_LIMIT;
  if (!plan.on(Effect::kPassive)) m->opt.disableflags |= mjDSBL_PASSIVE;
  if (!plan.on(Effect::kNativeContact)) m->opt.disableflags |= mjDSBL_CONTACT;

  // MuJoCo's sensors: those of an effect that is off leave every stage
  int computed = 0;
  for (int s = 0; s < m->nsensor; ++s) {
    if (KindOn(plan, KindOf(m, robot, s))) ++computed;
    else m->sensor_needstage[s] = mjSTAGE_NONE;
  }
  if (computed == 0) m->opt.disableflags |= mjDSBL_SENSOR;

  // switched-off pairs while native contact is on
  bool filter = false;
  if (plan.on(Effect::kNativeContact)) {
    for (const auto& cp : plan.pairs)
      if (!cp.on && !cp.soles) filter = true;
  }
  if (!filter) return;
  g_filter.m = m;
  g_filter.nbody = m->nbody;
  g_filter.off.assign(static_cast<size_t>(m->nbody) * m->nbody, 0);
  for (const auto& cp : plan.pairs) {
    if (cp.on) continue;
    g_filter.off[cp.body1 * m->nbody + cp.body2] = 1;
    g_filter.off[cp.body2 * m->nbody + cp.body1] = 1;
  }
  mjcb_contactfilter = ContactFilter;
}

void ClearContactFilter() {
  if (mjcb_contactfilter == ContactFilter) mjcb_contactfilter = nullptr;
  g_filter = Filter{};
}

}  // namespace ohrp::sim
