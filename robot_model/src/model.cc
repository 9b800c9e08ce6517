// Scene loading and the robot map (see model.h).
#include "robot_model/model.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "shm_bridge/layout.h"
#include "robot_model/load.h"

namespace ohrp::model {
namespace {

// suggested servo: a critically damped joint closing at kServoFrequency on its own inertia
constexpr double kServoFrequency = 6.0;  // [Hz]
constexpr double kServoDamping = 1.0;    // damping ratio [-]
constexpr double kLoadMargin = 2.0;  // a leg joint's stiffness over its load's gravity stiffness
// a motor leg joint's axis' vertical part closes at least at this frequency on the load it turns
// in single support (docs/robots.md, tall4: 6 Hz, the own-inertia rule's, made the tall robot's
// derived turn fall with the derived foot damping; 3 Hz passes all its walks)
constexpr double kYawLoadFrequency = 3.0;  // [Hz]
constexpr double kStepDamping = 0.25;  // the servo's kd dt / I_effective at most (explicit: < 2)
constexpr double kFootBand = 0.05;   // [m] bodies this close to the lowest are feet (qpos0)

// The servo gains suggested to controllers (default_kp, default_kd in the segment's header).
// A position servo the author built into the actuator (<position kp kv>) is the servo the
// robot was tuned with: its stiffness, and its damping (else critical damping of that
// stiffness on the joint's inertia). Otherwise (a <motor>): a critically damped joint closing
// at kServoFrequency on its own inertia at qpos0.
void SuggestGains(const ActuatorLaw& law, double inertia, double load_stiffness,
                  double max_damping, bool implicit_damping, double* kp, double* kd) {
  const double w = 2.0 * M_PI * kServoFrequency;
  *kp = inertia * w * w;
  *kd = 2.0 * kServoDamping * inertia * w;
  const double stiffness = law.Stiffness();
  if (stiffness > 0) {
    *kp = stiffness;
    *kd = law.Damping() > 0 ? law.Damping() : 2.0 * kServoDamping * std::sqrt(stiffness * inertia);
    // under MuJoCo's implicit integrator the author's damping is the actuator's own, taken
    // implicitly (G1); otherwise sim_host's servo applies it explicitly, as for a motor
    if (!implicit_damping) *kd = std::min(*kd, max_damping);
    return;
  }
  // a leg joint of a standing robot carries the body above it: at least kLoadMargin times the
  // gravity stiffness of that load, critically damped on the joint's own inertia
  if (load_stiffness > *kp) {
    *kp = load_stiffness;
    *kd = std::max(*kd, 2.0 * kServoDamping * std::sqrt(*kp * inertia));
  }
  // the servo's damping acts explicitly at every physics step: beyond max_damping (from the
  // joint's effective inertia and the step) it rings at the step's rate
  *kd = std::min(*kd, max_damping);
}

void (*g_on_fatal)(const char*) = nullptr;
std::atomic<long> g_warnings{0};
char g_last_warning[512] = "";

void OnMujocoError(const char* msg) {
  std::fprintf(stderr, "MuJoCo error: %s\n", msg);
  if (g_on_fatal) g_on_fatal(msg);
  std::_Exit(3);
}

void OnMujocoWarning(const char* msg) {
  g_warnings.fetch_add(1, std::memory_order_relaxed);
  std::snprintf(g_last_warning, sizeof(g_last_warning), "%s", msg);
}

std::string Name(const mjModel* m, int type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? std::string(n) : std::string();
}

// true when `body` is `root` or one of its descendants
bool InSubtree(const mjModel* m, int body, int root) {
  for (int b = body; b > 0; b = m->body_parentid[b]) {
    if (b == root) return true;
  }
  return false;
}

// The inertia about joint j's axis (through its anchor) of the robot's bodies outside the
// joint body jb's subtree: what the joint turns when its foot stands on the ground.
double LoadInertia(const mjModel* m, const mjData* d, int base_body, int jb, int j) {
  const double* a = d->xaxis + 3 * j;
  const double* p = d->xanchor + 3 * j;
  double inertia = 0;
  for (int b = base_body; b < m->nbody; ++b) {
    if (!InSubtree(m, b, base_body) || InSubtree(m, b, jb)) continue;
    const double* R = d->ximat + 9 * b;  // the body's principal axes (columns) in the world
    for (int k = 0; k < 3; ++k) {
      const double c = R[k] * a[0] + R[3 + k] * a[1] + R[6 + k] * a[2];
      inertia += m->body_inertia[3 * b + k] * c * c;
    }
    double r[3], along = 0;
    for (int k = 0; k < 3; ++k) along += (r[k] = d->xipos[3 * b + k] - p[k]) * a[k];
    double dist2 = 0;
    for (int k = 0; k < 3; ++k) dist2 += std::pow(r[k] - along * a[k], 2);
    inertia += m->body_mass[b] * dist2;
  }
  return inertia;
}

// The gravity stiffness of the load each leg joint carries when the robot stands on its feet:
// for a joint whose subtree holds one of the robot's lowest bodies (a foot, at qpos0), the mass
// outside its subtree, m_c, whose centre of mass stands h_c above the joint, tips about it with
// the stiffness m_c g h_c; two legs share it, and the floor asks kLoadMargin times the share.
// 0 for other joints and for a robot without a free base. (issue 31: a 70 kg robot of <motor>s
// with 0.01 kg m^2 rotors got 28 N m/rad at its ankles from the 6 Hz rule and fell under posture.)
std::vector<double> LoadStiffness(const mjModel* m, const mjData* d, int base_body) {
  std::vector<double> out(m->njnt, 0.0);
  if (base_body < 0) return out;
  double lowest = 1e300;
  for (int b = base_body; b < m->nbody; ++b)
    if (InSubtree(m, b, base_body)) lowest = std::min(lowest, d->xpos[3 * b + 2]);
  const double M = m->body_subtreemass[base_body];
  const double* c = d->subtree_com + 3 * base_body;
  for (int j = 0; j < m->njnt; ++j) {
    const int jb = m->jnt_bodyid[j];
    if (m->jnt_type[j] != mjJNT_HINGE || !InSubtree(m, jb, base_body) || jb == base_body) continue;
    bool holds_foot = false;
    for (int b = jb; b < m->nbody && !holds_foot; ++b)
      holds_foot = InSubtree(m, b, jb) && d->xpos[3 * b + 2] < lowest + kFootBand;
    const double m_sub = m->body_subtreemass[jb];
    const double m_c = M - m_sub;
    if (!holds_foot || m_c <= 0) continue;
    const double z_c = (M * c[2] - m_sub * d->subtree_com[3 * jb + 2]) / m_c;
    const double h_c = z_c - d->xanchor[3 * j + 2];
    // gravity tips the load about a horizontal axis only (a hip yaw carries none)
    const double* ax = d->xaxis + 3 * j;
    const double horizontal = std::sqrt(ax[0] * ax[0] + ax[1] * ax[1]);
    if (h_c > 0) out[j] = kLoadMargin * m_c * 9.81 * h_c * horizontal / 2.0;
    // about the axis' vertical part gravity holds nothing: in single support the stance leg's
    // joint alone turns the load (the rest of the robot) about it, so it closes at
    // kYawLoadFrequency on that inertia, not on its own (issue 31: the tall robot's hip yaws had
    // 46 N m/rad from their own inertia and yielded 0.08-0.14 rad at each step; it spun and
    // fell, and standing after a walk its base stayed 6 deg turned on its feet)
    const double w = 2.0 * M_PI * kYawLoadFrequency;
    out[j] = std::max(out[j], w * w * LoadInertia(m, d, base_body, jb, j) * ax[2] * ax[2]);
  }
  return out;
}

}  // namespace

void InstallMujocoHandlers(void (*on_fatal)(const char* message)) {
  g_on_fatal = on_fatal;
  mju_user_error = OnMujocoError;
  mju_user_warning = OnMujocoWarning;
}

long WarningCount() { return g_warnings.load(std::memory_order_relaxed); }
const char* LastWarning() { return g_last_warning; }

//---------------- scene ----------------

std::unique_ptr<Scene> Scene::Load(const std::string& path, std::string* error) {
  // a robot profile, an OpenHRP VRML file, MJCF or URDF (load.h)
  mjModel* m = LoadMujocoModel(path, error);
  if (!m) return nullptr;
  std::unique_ptr<Scene> scene(new Scene());
  scene->m_ = m;
  scene->d_ = mj_makeData(m);
  scene->path_ = path;
  if (!scene->d_) {
    *error = "cannot allocate mjData for '" + path + "'";
    return nullptr;
  }
  return scene;
}

Scene::~Scene() {
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

bool Scene::Reset(const std::string& keyframe, std::string* error) {
  if (keyframe.empty()) {
    mj_resetData(m_, d_);
  } else {
    const int key = mj_name2id(m_, mjOBJ_KEY, keyframe.c_str());
    if (key < 0) {
      *error = "scene '" + path_ + "' has no keyframe '" + keyframe + "'";
      return false;
    }
    mj_resetDataKeyframe(m_, d_, key);
  }
  mj_forward(m_, d_);
  return true;
}

//---------------- robot map ----------------

bool MapRobot(const mjModel* m, RobotMap* robot, std::string* error) {
  *robot = RobotMap{};
  robot->name = m->names[0] ? std::string(m->names) : std::string("robot");
  // the model's name only labels the segment (the model hash identifies it): a long name is
  // cut to the header's room rather than refusing the robot (issue 31: a generated model named
  // 'test_humanoid_camel_motor_1.1333_70', 35 bytes, was refused by sim_host)
  if (robot->name.size() >= static_cast<size_t>(shm::kNameLen))
    robot->name.resize(shm::kNameLen - 1);

  // base: the first free joint's body
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] == mjJNT_FREE) {
      robot->base_body = m->jnt_bodyid[j];
      robot->base_qpos = m->jnt_qposadr[j];
      robot->base_dof = m->jnt_dofadr[j];
      break;
    }
  }
  // mass: the base's subtree (not the free objects of the scene), or every body when fixed
  for (int b = 1; b < m->nbody; ++b) {
    if (robot->base_body < 0 || InSubtree(m, b, robot->base_body)) robot->total_mass += m->body_mass[b];
  }

  // joints: the targets of the actuators, in actuator order
  std::vector<mjtNum> M(static_cast<size_t>(m->nv) * m->nv);
  mjData* d = mj_makeData(m);
  mj_forward(m, d);
  mj_fullM(m, M.data(), d->qM);
  const std::vector<double> load_stiffness = LoadStiffness(m, d, robot->base_body);
  // each joint's effective inertia 1 / (M^-1)_jj: what a torque on it alone accelerates, the
  // other joints free (the swinging leg; co-located hip joints on light links make it far
  // smaller than M_jj)
  std::vector<mjtNum> unit(m->nv, 0.0), column(m->nv, 0.0);
  std::vector<double> effective(m->nv, 0.0);
  for (int v = 0; v < m->nv; ++v) {
    unit[v] = 1.0;
    mj_solveM(m, d, column.data(), unit.data(), 1);
    unit[v] = 0.0;
    effective[v] = column[v] > 0 ? 1.0 / column[v] : 0.0;
  }
  mj_deleteData(d);
  std::vector<int> driven_by(m->njnt, -1);  // actuator driving each joint
  for (int a = 0; a < m->nu; ++a) {
    JointMap jm;
    if (!ReadActuatorLaw(m, a, &jm.law, error)) return false;
    jm.actuator_id = a;
    jm.joint_id = m->actuator_trnid[2 * a];
    jm.name = Name(m, mjOBJ_JOINT, jm.joint_id);
    if (driven_by[jm.joint_id] >= 0) {
      *error = "joint '" + jm.name + "' is driven by actuators '" +
               Name(m, mjOBJ_ACTUATOR, driven_by[jm.joint_id]) + "' and '" +
               Name(m, mjOBJ_ACTUATOR, a) + "': the segment needs one actuator per joint";
      return false;
    }
    driven_by[jm.joint_id] = a;
    jm.qpos_adr = m->jnt_qposadr[jm.joint_id];
    jm.dof_adr = m->jnt_dofadr[jm.joint_id];
    if (m->jnt_limited[jm.joint_id]) {
      jm.q_min = m->jnt_range[2 * jm.joint_id];
      jm.q_max = m->jnt_range[2 * jm.joint_id + 1];
    } else {
      jm.q_min = -kNoLimit;
      jm.q_max = kNoLimit;
    }
    jm.tau_max = jm.law.TorqueLimit(kNoLimit);
    const double inertia = M[static_cast<size_t>(jm.dof_adr) * m->nv + jm.dof_adr];
    const double max_damping = kStepDamping * effective[jm.dof_adr] / m->opt.timestep;
    SuggestGains(jm.law, inertia, load_stiffness[jm.joint_id], max_damping,
                 m->opt.integrator == mjINT_IMPLICIT, &jm.default_kp, &jm.default_kd);
    robot->joints.push_back(jm);
  }
  if (robot->joints.empty()) {
    *error = "the model has no <motor> (or <position>, <velocity>, <general>) actuators: "
             "nothing for a controller to command";
    return false;
  }

  // passive joints: hinges and slides no actuator drives, within the robot (the base's subtree)
  for (int j = 0; j < m->njnt; ++j) {
    const int type = m->jnt_type[j];
    if ((type != mjJNT_HINGE && type != mjJNT_SLIDE) || driven_by[j] >= 0) continue;
    if (robot->base_body >= 0 && !InSubtree(m, m->jnt_bodyid[j], robot->base_body)) continue;
    std::string name = Name(m, mjOBJ_JOINT, j);
    if (name.empty()) name = "joint#" + std::to_string(j);  // the segment needs a name
    robot->passive.push_back({name, j, m->jnt_qposadr[j], m->jnt_dofadr[j]});
  }
  if (robot->passive.size() > static_cast<size_t>(shm::kMaxPassiveJoints)) {
    *error = "the robot has " + std::to_string(robot->passive.size()) +
             " passive joints (hinges and slides no actuator drives); the segment carries at "
             "most " + std::to_string(shm::kMaxPassiveJoints);
    return false;
  }
  if (robot->joints.size() > static_cast<size_t>(shm::kMaxJoints)) {
    *error = "the robot has " + std::to_string(robot->joints.size()) +
             " motors; the segment carries at most " + std::to_string(shm::kMaxJoints);
    return false;
  }

  // force/torque sensors and IMUs: sensor pairs on one site
  auto find_on_site = [m](int type, int site) {
    for (int s = 0; s < m->nsensor; ++s) {
      if (m->sensor_type[s] == type && m->sensor_objtype[s] == mjOBJ_SITE &&
          m->sensor_objid[s] == site)
        return m->sensor_adr[s];
    }
    return -1;
  };
  // the sensors of a pair without its partner are said, not dropped silently
  constexpr const char* kFtPairs = "force/torque pairs";
  constexpr const char* kImuPairs = "IMUs: gyro and accelerometer pairs";
  const auto lone = [&](int s, const char* kind, const char* partner, const char* carried) {
    const std::string name = Name(m, mjOBJ_SENSOR, s);
    robot->unpublished.push_back(std::string("<") + kind + "> sensor" + (name.empty() ? "" : " '" + name + "'") +
                                 " on site '" + Name(m, mjOBJ_SITE, m->sensor_objid[s]) + "' has no <" +
                                 partner + "> on the same site: not published (the segment carries " +
                                 carried + ")");
  };
  for (int s = 0; s < m->nsensor; ++s) {
    if (m->sensor_objtype[s] != mjOBJ_SITE) continue;
    const int site = m->sensor_objid[s];
    const int type = m->sensor_type[s];
    if (type == mjSENS_FORCE) {
      const int t = find_on_site(mjSENS_TORQUE, site);
      if (t < 0) {
        lone(s, "force", "torque", kFtPairs);
        continue;
      }
      robot->forces.push_back({Name(m, mjOBJ_SITE, site), site, m->sensor_adr[s], t});
    } else if (type == mjSENS_GYRO) {
      const int acc = find_on_site(mjSENS_ACCELEROMETER, site);
      if (acc < 0) {
        lone(s, "gyro", "accelerometer", kImuPairs);
        continue;
      }
      robot->imus.push_back({Name(m, mjOBJ_SITE, site), site, m->sensor_adr[s], acc,
                             find_on_site(mjSENS_FRAMEQUAT, site)});
    } else if (type == mjSENS_TORQUE && find_on_site(mjSENS_FORCE, site) < 0) {
      lone(s, "torque", "force", kFtPairs);
    } else if (type == mjSENS_ACCELEROMETER && find_on_site(mjSENS_GYRO, site) < 0) {
      lone(s, "accelerometer", "gyro", kImuPairs);
    }
  }
  // more than the segment carries: the first ones (model order) are published, the others
  // named as not published, the robot is not refused for them
  const auto beyond = [&](const std::string& site, const char* what, int most) {
    robot->unpublished.push_back(std::string(what) + " on site '" + site + "': not published (the segment carries " +
                                 std::to_string(most) + ", the first in the model's order)");
  };
  for (size_t f = shm::kMaxForceSensors; f < robot->forces.size(); ++f)
    beyond(robot->forces[f].name, "force/torque sensor", shm::kMaxForceSensors);
  for (size_t i = shm::kMaxImus; i < robot->imus.size(); ++i)
    beyond(robot->imus[i].name, "IMU", shm::kMaxImus);
  if (robot->forces.size() > static_cast<size_t>(shm::kMaxForceSensors))
    robot->forces.resize(shm::kMaxForceSensors);
  if (robot->imus.size() > static_cast<size_t>(shm::kMaxImus)) robot->imus.resize(shm::kMaxImus);
  for (int c = 0; c < m->ncam && c < shm::kMaxCameras; ++c) {
    robot->cameras.push_back({Name(m, mjOBJ_CAMERA, c), c, m->cam_bodyid[c]});
  }
  return true;
}

//---------------- keyframes ----------------

bool KeyframeJointPositions(const mjModel* m, const std::string& key,
                            std::vector<std::pair<std::string, double>>* out, std::string* error) {
  out->clear();
  const int k = mj_name2id(m, mjOBJ_KEY, key.c_str());
  if (k < 0) {
    std::string names;
    for (int i = 0; i < m->nkey; ++i) names += (i ? ", " : "") + Name(m, mjOBJ_KEY, i);
    *error = "the scene has no keyframe '" + key + "' (" +
             (m->nkey ? "its keyframes: " + names : std::string("it has none")) + ")";
    return false;
  }
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    out->emplace_back(Name(m, mjOBJ_JOINT, j), m->key_qpos[k * m->nq + m->jnt_qposadr[j]]);
  }
  return true;
}

//---------------- explanation ----------------

std::string DescribeActuation(const RobotMap& robot) {
  std::string s = "actuation (" + std::to_string(robot.joints.size()) +
                  " commanded joints: the servo's joint torque becomes each actuator's ctrl):\n";
  char limit[64];
  for (const JointMap& j : robot.joints) {
    if (j.tau_max >= kNoLimit) {
      std::snprintf(limit, sizeof limit, "no torque limit");
    } else {
      std::snprintf(limit, sizeof limit, "torque limit %g", j.tau_max);
    }
    s += "  " + j.name + ": " + j.law.Describe() + "; " + limit + "\n";
  }
  s += "passive joints (" + std::to_string(robot.passive.size()) + ", read-only):";
  if (robot.passive.empty()) s += " none";
  for (const PassiveJointMap& p : robot.passive) s += " " + p.name;
  return s + "\n";
}

}  // namespace ohrp::model
