// The effects' defaults: what the scene, the contact choice and the log declare, each with its
// reason (step 1 of ResolveEffects; effects_internal.h).
#include <cstdio>
#include <map>

#include "collision/from_mjcf.h"
#include "effects_internal.h"

namespace ohrp::sim::effects_internal {

bool DeclareDefaults(const mjModel* m, const model::RobotMap& robot, const FeetOptions& feet, bool log,
                     EffectsPlan* plan) {
  EffectsPlan& p = *plan;
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
  const ContactModel model = ResolveContactModel(m, feet, soles);
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
    declare(Effect::kSelfContact, true, true,
            std::to_string(self_pairs) + " body pairs within one robot can collide");
  else
    declare(Effect::kSelfContact, false, false,
            "the scene lets no two bodies of one robot collide (contype/conaffinity, <exclude>)");

  // self-collision report: the controllers' checker on the robot's links (no physics)
  collision::RobotGeometry geometry;
  std::string why;
  if (!collision::GeometryFromModel(m, robot, &geometry, &why)) {
    declare(Effect::kSelfCollision, false, false, "the robot's geometry cannot be checked: " + why);
  } else if (const size_t n = collision::NonAdjacentPairs(geometry).size(); n == 0) {
    declare(Effect::kSelfCollision, false, false, "the robot has no two non-adjacent links with geoms");
  } else {
    declare(Effect::kSelfCollision, true, false,
            "not asked for (--effects self_collision=on, --self-collision FILE, or a scenario's "
            "self_collisions check): the robot's " + std::to_string(geometry.links.size()) +
                " links have " + std::to_string(n) + " non-adjacent pairs to check");
  }

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
  return soft;
}

}  // namespace ohrp::sim::effects_internal
