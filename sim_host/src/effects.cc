// Effects resolution (see effects.h and docs/effects.md).
#include "sim_host/effects.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>

namespace ohrp::sim {
namespace {

constexpr const char* kNames[kEffectCount] = {
    "gravity",        "joint_limits", "passive",      "native_contact", "self_collision",
    "soft_contact",   "encoders",     "joint_velocities", "joint_torques", "force_torque",
    "gyro",           "accelerometer", "orientation", "rne_post",       "other_sensors",
    "noise",          "cameras",      "log",          "log_base",       "log_joints",
    "log_force_torque", "log_imu"};

int I(Effect e) { return static_cast<int>(e); }

// what each effect needs to be computed
std::vector<Effect> Needs(Effect e) {
  switch (e) {
    case Effect::kSelfCollision: return {Effect::kNativeContact};
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

std::string BodyName(const mjModel* m, int b) {
  const char* n = mj_id2name(m, mjOBJ_BODY, b);
  return n ? std::string(n) : (b == 0 ? std::string("world") : "body" + std::to_string(b));
}

std::string GeomName(const mjModel* m, int g) {
  const char* n = mj_id2name(m, mjOBJ_GEOM, g);
  return n ? std::string(n) : "geom" + std::to_string(g);
}

std::string Join(const std::vector<std::string>& v, size_t max = 6) {
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

enum class SensorKind { kForceTorque, kGyro, kAccel, kOrientation, kOther };

// which effect reads MuJoCo sensor `s`
SensorKind KindOf(const mjModel* m, const RobotMap& robot, int s) {
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

//---------------- names and requests ----------------

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
      for (int i = 0; i < kEffectCount; ++i) known += (i ? " " : "") + std::string(kNames[i]);
      *error = "effects: unknown effect '" + key + "' (known: " + known +
               ", contact:BODY1/BODY2, noise.KIND)";
      return false;
    }
    out->request[I(e)] = state;
  }
  return true;
}

//---------------- resolution ----------------

bool ResolveEffects(const mjModel* m, const RobotMap& robot, const FeetOptions& feet, bool log,
                    const EffectRequests& req, EffectsPlan* plan, std::string* error) {
  EffectsPlan p;
  p.noise = req.noise;
  auto& E = p.effects;
  auto declare = [&](Effect e, bool declared, bool on, const std::string& reason) {
    E[I(e)].declared = declared;
    E[I(e)].on = on;
    E[I(e)].reason = reason;
  };
  char buf[256];
  const int flags = m->opt.disableflags;

  // physics the scene declares
  const double g = mju_norm3(m->opt.gravity);
  if (flags & mjDSBL_GRAVITY) declare(Effect::kGravity, false, false, "switched off by the scene's <flag>");
  else if (g > 0) {
    std::snprintf(buf, sizeof(buf), "the scene's gravity (%g, %g, %g) m/s^2", m->opt.gravity[0],
                  m->opt.gravity[1], m->opt.gravity[2]);
    declare(Effect::kGravity, true, true, buf);
  } else declare(Effect::kGravity, false, false, "the scene's gravity is zero");

  int limited = 0, limited_tendons = 0;
  for (int j = 0; j < m->njnt; ++j) limited += m->jnt_limited[j] != 0;
  for (int t = 0; t < m->ntendon; ++t) limited_tendons += m->tendon_limited[t] != 0;
  if (flags & mjDSBL_LIMIT) declare(Effect::kJointLimits, false, false, "switched off by the scene's <flag>");
  else if (limited + limited_tendons > 0) {
    std::snprintf(buf, sizeof(buf), "the scene limits %d joints and %d tendons", limited, limited_tendons);
    declare(Effect::kJointLimits, true, true, buf);
  } else declare(Effect::kJointLimits, false, false, "no limited joint or tendon in the scene");

  int springs = 0, dampers = 0;
  for (int j = 0; j < m->njnt; ++j) springs += m->jnt_stiffness[j] > 0;
  for (int v = 0; v < m->nv; ++v) dampers += m->dof_damping[v] > 0;
  for (int t = 0; t < m->ntendon; ++t) {
    springs += m->tendon_stiffness[t] > 0;
    dampers += m->tendon_damping[t] > 0;
  }
  const bool fluid = m->opt.density > 0 || m->opt.viscosity > 0;
  if (flags & mjDSBL_PASSIVE) declare(Effect::kPassive, false, false, "switched off by the scene's <flag>");
  else if (springs + dampers > 0 || fluid) {
    std::snprintf(buf, sizeof(buf), "the scene has %d springs and %d dampers (joints, tendons)%s",
                  springs, dampers, fluid ? " and a fluid" : "");
    declare(Effect::kPassive, true, true, buf);
  } else declare(Effect::kPassive, false, false, "no spring, damper or fluid in the scene");

  // contact: the soles, the pairs MuJoCo could make touch
  const std::vector<int> soles = Soles(m, feet);
  ContactModel model = feet.model;
  if (model == ContactModel::kAuto) model = soles.empty() ? ContactModel::kNative : ContactModel::kSoft;
  const bool soft = model == ContactModel::kSoft;
  std::vector<std::string> sole_names;
  for (int s : soles) sole_names.push_back(GeomName(m, s));
  if (soft) {
    declare(Effect::kSoftContact, true, true,
            std::string(feet.model == ContactModel::kAuto ? "--contact auto (the model has soles): "
                                                          : "--contact soft: ") +
                "the soles " + Join(sole_names) + " on the paper's spring-damper");
  } else {
    declare(Effect::kSoftContact, !soles.empty(), false,
            std::string("--contact ") + ContactModelName(model) +
                (soles.empty() ? " (the model has no *_SOLE geoms)" : ""));
  }
  p.pairs = CandidatePairs(m, soles);
  int self_pairs = 0, native_pairs = 0;
  for (const auto& cp : p.pairs) {
    if (cp.soles && soft) continue;
    ++native_pairs;
    self_pairs += cp.self;
  }
  if (flags & mjDSBL_CONTACT) {
    declare(Effect::kNativeContact, false, false, "switched off by the scene's <flag>");
  } else if (native_pairs > 0) {
    declare(Effect::kNativeContact, true, true,
            std::to_string(native_pairs) + " body pairs of the scene can touch");
  } else {
    declare(Effect::kNativeContact, false, false,
            p.pairs.empty() ? "no geom pair of the scene can collide (contype/conaffinity, <exclude>)"
                            : "the only colliding geoms are the soles, on the soft-foot contact");
  }
  if (self_pairs > 0 && !(flags & mjDSBL_CONTACT))
    declare(Effect::kSelfCollision, true, true,
            std::to_string(self_pairs) + " body pairs within one robot can collide");
  else
    declare(Effect::kSelfCollision, false, false,
            "the scene lets no two bodies of one robot collide (contype/conaffinity, <exclude>)");

  // sensors: what the segment carries
  const size_t nj = robot.joints.size();
  const std::string joints = std::to_string(nj) + " joints";
  declare(Effect::kEncoders, nj > 0, nj > 0,
          nj ? "the segment carries q of " + joints + " (read from the state)" : "no joints");
  declare(Effect::kJointVelocities, nj > 0, nj > 0,
          nj ? "the segment carries dq of " + joints + " (read from the state)" : "no joints");
  declare(Effect::kJointTorques, nj > 0, nj > 0,
          nj ? "the segment carries tau of " + joints + " (the servo's output)" : "no joints");
  std::vector<std::string> fts, imus;
  for (const auto& f : robot.forces) fts.push_back(f.name);
  for (const auto& u : robot.imus) imus.push_back(u.name);
  declare(Effect::kForceTorque, !fts.empty(), !fts.empty(),
          fts.empty() ? "the scene declares no F/T sensor (<force> + <torque> on one site)"
                      : "the scene declares " + std::to_string(fts.size()) + " F/T sensors (" + Join(fts) + ")");
  const std::string imu_text = imus.empty() ? "the scene declares no IMU (<gyro> + <accelerometer> on one site)"
                                            : "the scene declares the IMU " + Join(imus);
  declare(Effect::kGyro, !imus.empty(), !imus.empty(), imu_text);
  declare(Effect::kAccelerometer, !imus.empty(), !imus.empty(), imu_text);
  declare(Effect::kOrientation, !imus.empty(), !imus.empty(), imu_text);
  declare(Effect::kRnePost, true, false, "nothing reads body accelerations or internal forces");
  std::map<std::string, int> other;  // MuJoCo sensor type -> count
  int nother = 0;
  static const std::map<int, const char*> kTypeNames = {
      {mjSENS_JOINTPOS, "jointpos"}, {mjSENS_JOINTVEL, "jointvel"},
      {mjSENS_ACTUATORFRC, "actuatorfrc"}, {mjSENS_FORCE, "force"}, {mjSENS_TORQUE, "torque"},
      {mjSENS_GYRO, "gyro"}, {mjSENS_ACCELEROMETER, "accelerometer"},
      {mjSENS_FRAMEQUAT, "framequat"}, {mjSENS_TOUCH, "touch"}};
  for (int s = 0; s < m->nsensor; ++s) {
    if (KindOf(m, robot, s) != SensorKind::kOther) continue;
    auto it = kTypeNames.find(m->sensor_type[s]);
    ++other[it == kTypeNames.end() ? "other" : it->second];
    ++nother;
  }
  std::string other_text;
  for (const auto& kv : other) other_text += (other_text.empty() ? "" : ", ") + std::to_string(kv.second) + " " + kv.first;
  declare(Effect::kOtherSensors, nother > 0, false,
          nother ? std::to_string(nother) + " MuJoCo sensors of the scene (" + other_text +
                       ") have no reader: the segment's q, dq, tau come from the state"
                 : "every MuJoCo sensor of the scene is published");
  const bool any_sensor = nj > 0 || !fts.empty() || !imus.empty();
  declare(Effect::kNoise, any_sensor, false, "not asked for (--effects noise=on)");
  std::vector<std::string> cams;
  for (int c = 0; c < m->ncam; ++c) {
    const char* n = mj_id2name(m, mjOBJ_CAMERA, c);
    cams.push_back(n ? n : "camera" + std::to_string(c));
  }
  declare(Effect::kCameras, !cams.empty(), !cams.empty(),
          cams.empty() ? "the scene declares no camera"
                       : "declared by the scene (" + Join(cams) + "): rendered only while an attached "
                         "program asks for images (none asks: nothing set up, no cost)");

  // the log and its channels
  declare(Effect::kLog, log, log, log ? "--log" : "no --log");
  declare(Effect::kLogBase, log, log,
          !log ? "no --log"
          : robot.base_body >= 0 ? "the log records the base's ground truth"
                                 : "the log records the base's ground truth (zeros: the robot has no free base)");
  declare(Effect::kLogJoints, log && nj > 0, log && nj > 0, log ? "the log records q, qref, tau" : "no --log");
  declare(Effect::kLogForceTorque, log && !fts.empty(), log && !fts.empty(),
          log ? "the log records the F/T sensors" : "no --log");
  declare(Effect::kLogImu, log && !imus.empty(), log && !imus.empty(),
          log ? "the log records the IMUs" : "no --log");

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
    } else if (cp.self && !p.on(Effect::kSelfCollision)) {
      cp.on = false;
      cp.reason = "self_collision is off";
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

//---------------- applying the plan ----------------

void ApplyEffects(const EffectsPlan& plan, const RobotMap& robot, mjModel* m) {
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

//---------------- the table ----------------

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

//---------------- sensors and noise ----------------

SensorSelection SelectSensors(const EffectsPlan& p) {
  SensorSelection s;
  s.q = p.on(Effect::kEncoders);
  s.dq = p.on(Effect::kJointVelocities);
  s.tau = p.on(Effect::kJointTorques);
  s.force_torque = p.on(Effect::kForceTorque);
  s.gyro = p.on(Effect::kGyro);
  s.accel = p.on(Effect::kAccelerometer);
  s.orientation = p.on(Effect::kOrientation);
  return s;
}

SensorNoise::SensorNoise(const NoiseOptions& options, const SensorSelection& selection)
    : o_(options), sel_(selection), rng_(options.seed) {}

void SensorNoise::Apply(const RobotMap& robot, shm::SensorBlock* s) {
  const int nj = static_cast<int>(robot.joints.size());
  if (sel_.q && o_.q > 0)
    for (int i = 0; i < nj; ++i) s->q[i] += o_.q * Gauss();
  if (sel_.dq && o_.dq > 0)
    for (int i = 0; i < nj; ++i) s->dq[i] += o_.dq * Gauss();
  if (sel_.tau && o_.tau > 0)
    for (int i = 0; i < nj; ++i) s->tau[i] += o_.tau * Gauss();
  if (sel_.force_torque) {
    for (size_t f = 0; f < robot.forces.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (o_.force > 0) s->force[f].force[k] += o_.force * Gauss();
        if (o_.torque > 0) s->force[f].torque[k] += o_.torque * Gauss();
      }
    }
  }
  for (size_t u = 0; u < robot.imus.size(); ++u) {
    shm::Imu& imu = s->imu[u];
    for (int k = 0; k < 3; ++k) {
      if (sel_.gyro && o_.gyro > 0) imu.gyro[k] += o_.gyro * Gauss();
      if (sel_.accel && o_.accel > 0) imu.accel[k] += o_.accel * Gauss();
    }
    if (sel_.orientation && o_.orientation > 0) {
      // a small rotation, its vector Gaussian per axis, applied in the IMU's frame
      double v[3] = {o_.orientation * Gauss(), o_.orientation * Gauss(), o_.orientation * Gauss()};
      const double angle = mju_norm3(v);
      double dq[4] = {1, 0, 0, 0};
      if (angle > 0) {
        const double sn = std::sin(0.5 * angle) / angle;
        dq[0] = std::cos(0.5 * angle);
        for (int k = 0; k < 3; ++k) dq[1 + k] = sn * v[k];
      }
      double q[4];
      mju_mulQuat(q, imu.quat_WI, dq);
      mju_normalize4(q);
      for (int k = 0; k < 4; ++k) imu.quat_WI[k] = q[k];
    }
  }
}

}  // namespace ohrp::sim
