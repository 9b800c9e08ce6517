// The scene queries of the effects module (effects_internal.h): names, the soles, MuJoCo's
// collision rules and the candidate contact pairs, the sensors' kinds.
#include <map>

#include "effects_internal.h"

namespace ohrp::sim::effects_internal {
namespace {

bool Excluded(const mjModel* m, int b1, int b2) {
  // MuJoCo's signature: (body1 + 1) << 16 | (body2 + 1)
  const int sig1 = ((b1 + 1) << 16) + b2 + 1, sig2 = ((b2 + 1) << 16) + b1 + 1;
  for (int i = 0; i < m->nexclude; ++i)
    if (m->exclude_signature[i] == sig1 || m->exclude_signature[i] == sig2) return true;
  return false;
}

bool NoCollider(int t1, int t2) {
  auto flat = [](int t) { return t == mjGEOM_PLANE || t == mjGEOM_HFIELD; };
  return flat(t1) && flat(t2);
}

}  // namespace

std::string BodyName(const mjModel* m, int b) {
  const char* n = mj_id2name(m, mjOBJ_BODY, b);
  return n ? std::string(n) : (b == 0 ? std::string("world") : "body" + std::to_string(b));
}

std::string GeomName(const mjModel* m, int g) {
  const char* n = mj_id2name(m, mjOBJ_GEOM, g);
  return n ? std::string(n) : "geom" + std::to_string(g);
}

std::string Join(const std::vector<std::string>& v, size_t max) {
  std::string s;
  for (size_t i = 0; i < v.size() && i < max; ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > max) s += ", ... (" + std::to_string(v.size()) + ")";
  return s;
}

// the sole geoms as SetUpFeet finds them: named, or every "*_SOLE" geom
std::vector<int> Soles(const mjModel* m, const FeetOptions& feet) {
  std::vector<int> ids;
  if (!feet.soles.empty()) {
    for (const auto& s : feet.soles) {
      const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str());
      if (g >= 0) ids.push_back(g);
    }
    return ids;
  }
  for (int g = 0; g < m->ngeom; ++g) {
    const std::string n = GeomName(m, g);
    if (n.size() > 5 && n.compare(n.size() - 5, 5, "_SOLE") == 0) ids.push_back(g);
  }
  return ids;
}

bool BitmaskAllows(const mjModel* m, int g1, int g2) {
  return (m->geom_contype[g1] & m->geom_conaffinity[g2]) ||
         (m->geom_contype[g2] & m->geom_conaffinity[g1]);
}

bool ParentFiltered(const mjModel* m, int b1, int b2) {
  if (m->opt.disableflags & mjDSBL_FILTERPARENT) return false;
  const int w1 = m->body_weldid[b1], w2 = m->body_weldid[b2];
  if (w1 == 0 || w2 == 0) return false;  // the world is nobody's filtered parent
  const int p1 = m->body_weldid[m->body_parentid[w1]];
  const int p2 = m->body_weldid[m->body_parentid[w2]];
  return p1 == w2 || p2 == w1;
}

// the body pairs of the scene whose geoms MuJoCo's contact can make touch
std::vector<ContactPair> CandidatePairs(const mjModel* m, const std::vector<int>& soles) {
  std::map<std::pair<int, int>, ContactPair> pairs;
  auto add = [&](int g1, int g2) {
    int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
    if (b1 > b2) std::swap(b1, b2);
    ContactPair& p = pairs[{b1, b2}];
    p.body1 = b1;
    p.body2 = b2;
    p.name = BodyName(m, b1) + "/" + BodyName(m, b2);
    p.self = m->body_rootid[b1] == m->body_rootid[b2] && m->body_rootid[b1] != 0;
    ++p.geom_pairs;
    for (int s : soles)
      if (s == g1 || s == g2) p.soles = true;
  };
  for (int g1 = 0; g1 < m->ngeom; ++g1) {
    for (int g2 = g1 + 1; g2 < m->ngeom; ++g2) {
      const int b1 = m->geom_bodyid[g1], b2 = m->geom_bodyid[g2];
      if (m->body_weldid[b1] == m->body_weldid[b2]) continue;  // one rigid body (or both static)
      if (!BitmaskAllows(m, g1, g2) || NoCollider(m->geom_type[g1], m->geom_type[g2])) continue;
      if (ParentFiltered(m, b1, b2) || Excluded(m, b1, b2)) continue;
      add(g1, g2);
    }
  }
  for (int i = 0; i < m->npair; ++i) add(m->pair_geom1[i], m->pair_geom2[i]);  // explicit <pair>
  std::vector<ContactPair> out;
  for (auto& kv : pairs) out.push_back(kv.second);
  return out;
}

// which effect reads MuJoCo sensor `s`
SensorKind KindOf(const mjModel* m, const model::RobotMap& robot, int s) {
  const int adr = m->sensor_adr[s];
  for (const auto& f : robot.forces)
    if (adr == f.force_adr || adr == f.torque_adr) return SensorKind::kForceTorque;
  for (const auto& u : robot.imus) {
    if (adr == u.gyro_adr) return SensorKind::kGyro;
    if (adr == u.accel_adr) return SensorKind::kAccel;
    if (adr == u.quat_adr) return SensorKind::kOrientation;
  }
  return SensorKind::kOther;
}

bool KindOn(const EffectsPlan& p, SensorKind k) {
  switch (k) {
    case SensorKind::kForceTorque: return p.on(Effect::kForceTorque);
    case SensorKind::kGyro: return p.on(Effect::kGyro);
    case SensorKind::kAccel: return p.on(Effect::kAccelerometer);
    case SensorKind::kOrientation: return p.on(Effect::kOrientation);
    case SensorKind::kOther: return p.on(Effect::kOtherSensors);
  }
  return false;
}

}  // namespace ohrp::sim::effects_internal
