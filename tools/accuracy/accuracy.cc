// Speed-accuracy measurement (see accuracy.h).
#include "accuracy.h"
#include "robot_model/load.h"
#include "shm_bridge/clock.h"

#include <time.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

namespace ohrp::accuracy {

const char* IntegratorName(Integrator i) {
  switch (i) {
    case Integrator::kEuler: return "euler";
    case Integrator::kRK4: return "rk4";
    case Integrator::kImplicit: return "implicit";
  }
  return "?";
}

bool ParseIntegrator(const std::string& name, Integrator* out) {
  if (name == "euler") *out = Integrator::kEuler;
  else if (name == "rk4") *out = Integrator::kRK4;
  else if (name == "implicit") *out = Integrator::kImplicit;
  else return false;
  return true;
}

const char* ContactName(Contact c) {
  switch (c) {
    case Contact::kNone: return "none";
    case Contact::kSoft: return "soft";
    case Contact::kNative: return "native";
    case Contact::kRigid: return "rigid";
  }
  return "?";
}

bool ParseContact(const std::string& name, Contact* out) {
  if (name == "none") *out = Contact::kNone;
  else if (name == "soft") *out = Contact::kSoft;
  else if (name == "native") *out = Contact::kNative;
  else if (name == "rigid") *out = Contact::kRigid;
  else return false;
  return true;
}

std::string Describe(const Setting& s) {
  std::ostringstream o;
  o << IntegratorName(s.integrator) << " dt=" << s.dt * 1e3 << "ms contact=" << ContactName(s.contact);
  if (s.iterations >= 0) o << " iter=" << s.iterations;
  if (s.tolerance >= 0) o << " tol=" << s.tolerance;
  if (!s.geometry.empty()) o << " geom=" << s.geometry;
  return o.str();
}

bool LoadWalk(const std::string& dir, Walk* walk, std::string* error) {
  using controllers::ConfigStatus;
  ConfigStatus s = controllers::LoadTrajectory(dir + "/angle.dat", &walk->angles);
  if (s.ok()) s = controllers::LoadTrajectory(dir + "/vel.dat", &walk->velocities);
  if (s.ok()) s = controllers::CheckCompanion(walk->angles, walk->velocities);
  if (s.ok()) s = controllers::LoadGains(dir + "/PDgain.dat", &walk->gains);
  if (!s.ok()) {
    *error = "SamplePD walking data in " + dir + ": " + s.message;
    return false;
  }
  if (static_cast<int>(walk->gains.kp.size()) != walk->angles.njoint) {
    *error = dir + "/PDgain.dat: gains for " + std::to_string(walk->gains.kp.size()) +
             " joints, angle.dat has " + std::to_string(walk->angles.njoint);
    return false;
  }
  return true;
}

namespace {

mjModel* LoadXmlString(const std::string& xml, std::string* error) {
  mjVFS vfs;
  mj_defaultVFS(&vfs);
  const char* name = "bench_scene.xml";
  if (mj_makeEmptyFileVFS(&vfs, name, static_cast<int>(xml.size())) != 0) {
    *error = "cannot make the VFS file";
    return nullptr;
  }
  std::memcpy(vfs.filedata[vfs.nfile - 1], xml.data(), xml.size());
  char err[1000] = "";
  mjModel* m = mj_loadXML(name, &vfs, err, sizeof(err));
  mj_deleteVFS(&vfs);
  if (!m) *error = std::string("inline scene: ") + err;
  return m;
}

}  // namespace

std::unique_ptr<Sim> Sim::Create(const SceneSpec& scene, const Setting& setting,
                                 std::string* error) {
  std::unique_ptr<Sim> s(new Sim());
  s->setting_ = setting;
  s->scene_ = &scene;
  if (!scene.path.empty()) {
    s->m_ = model::LoadMujocoModel(scene.path, error);  // a profile, VRML, MJCF, URDF
    if (!s->m_) return nullptr;
  } else {
    s->m_ = LoadXmlString(scene.xml, error);
    if (!s->m_) return nullptr;
  }
  mjModel* m = s->m_;
  m->opt.timestep = setting.dt;
  m->opt.integrator = setting.integrator == Integrator::kEuler  ? mjINT_EULER
                      : setting.integrator == Integrator::kRK4 ? mjINT_RK4
                                                               : mjINT_IMPLICIT;
  if (setting.iterations >= 0) m->opt.iterations = setting.iterations;
  if (setting.tolerance >= 0) m->opt.tolerance = setting.tolerance;
  // collision geometry variant: only the chosen geom collides
  if (!scene.geometries.empty()) {
    const std::string chosen = setting.geometry.empty() ? scene.geometries[0] : setting.geometry;
    bool found = false;
    for (const std::string& g : scene.geometries) {
      const int id = mj_name2id(m, mjOBJ_GEOM, g.c_str());
      if (id < 0) {
        *error = "scene " + scene.name + ": no geometry variant geom '" + g + "'";
        return nullptr;
      }
      const bool on = g == chosen;
      found = found || on;
      m->geom_contype[id] = on ? 1 : 0;
      m->geom_conaffinity[id] = on ? 1 : 0;
    }
    if (!found) {
      *error = "scene " + scene.name + " has no geometry variant '" + chosen + "'";
      return nullptr;
    }
  }
  if (setting.contact != Contact::kNone) {
    sim::FeetOptions feet;
    feet.model = setting.contact == Contact::kSoft    ? sim::ContactModel::kSoft
                 : setting.contact == Contact::kRigid ? sim::ContactModel::kRigid
                                                      : sim::ContactModel::kNative;
    feet.soles = scene.soles;
    if (setting.contact == Contact::kSoft && !setting.geometry.empty() &&
        !scene.geometries.empty() && setting.geometry != scene.geometries[0]) {
      *error = "the soft-foot contact samples a box sole: no geometry variants";
      return nullptr;
    }
    if (setting.contact == Contact::kRigid && !setting.geometry.empty()) {
      feet.soles = {setting.geometry};
    }
    std::string why;
    if (!sim::SetUpFeet(m, feet, 2 * scene.soft_mass, &s->soft_, &why)) {
      *error = (why.find("refused") != std::string::npos ? "refused: " : "") + why;
      return nullptr;
    }
  }
  s->d_ = mj_makeData(m);
  if (!scene.keyframe.empty()) {
    const int key = mj_name2id(m, mjOBJ_KEY, scene.keyframe.c_str());
    if (key < 0) {
      *error = "scene " + scene.name + ": no keyframe '" + scene.keyframe + "'";
      return nullptr;
    }
    mj_resetDataKeyframe(m, s->d_, key);
  }
  mj_forward(m, s->d_);
  if (scene.servo || scene.walk) {
    if (!model::MapRobot(m, &s->robot_, error)) return nullptr;
    s->servo_ = std::make_unique<model::Servo>(s->robot_);
    s->servo_->HoldCurrent(s->d_);
    const int n = static_cast<int>(s->robot_.joints.size());
    if (scene.walk && scene.walk->angles.njoint != n) {
      *error = "the walking data has " + std::to_string(scene.walk->angles.njoint) +
               " joints, the robot " + std::to_string(n);
      return nullptr;
    }
    s->q_ref_.assign(n, 0.0);
    s->dq_ref_.assign(n, 0.0);
    s->commands_.njoint = n;
  }
  s->step_ = std::make_unique<sim::PhysicsStep>(s->m_, s->d_,
                                                sim::PhysicsStep::Parts{s->servo_.get(), s->soft_.get()});
  return s;
}

Sim::~Sim() {
  if (d_) mj_deleteData(d_);
  if (m_) mj_deleteModel(m_);
}

void Sim::Controls() {
  if (!scene_->walk || !servo_) return;
  const Walk& w = *scene_->walk;
  const double t = d_->time;  // simulated time, never the step count
  controllers::SampleTrajectory(w.angles, t, q_ref_.data());
  if (t < w.angles.end_time()) {
    controllers::SampleTrajectory(w.velocities, t, dq_ref_.data());
  } else {
    std::fill(dq_ref_.begin(), dq_ref_.end(), 0.0);
  }
  for (int j = 0; j < commands_.njoint; ++j) {
    shm::JointCommand& c = commands_.joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q_ref_[j];
    c.dq_ref = dq_ref_[j];
    c.tau_ff = 0;
    c.kp = w.gains.kp[j];
    c.kd = w.gains.kd[j];
  }
  servo_->Accept(commands_);
}

double Sim::NormalForce() const {
  double f = 0;
  for (int i = 0; i < d_->ncon; ++i) {
    if (d_->contact[i].efc_address < 0) continue;
    mjtNum r[6];
    mj_contactForce(m_, d_, i, r);
    f += r[0];
  }
  return f;
}

double Sim::Step() {
  Controls();
  double f = 0;
  const bool stages = soft_ && soft_->at_every_stage();
  if (stages) {
    // RK4: mj_step evaluates the contact at each stage; its force at the step's start (the
    // one recorded, as for the other integrators) needs its own evaluation here
    contact::SoftFootContact::UpdateKinematics(m_, d_);
    for (const auto& w : soft_->Evaluate(m_, d_)) f += w.normal_force;
  }
  step_->Step();  // sim_host's step: servo, soft soles, mj_step, commit
  if (soft_ && !stages) {
    // the force held over the step (the implicit step's), along the soles' mean normal
    Eigen::Vector3d normal = Eigen::Vector3d::Zero(), force = Eigen::Vector3d::Zero();
    for (const auto& w : soft_->wrenches()) normal += w.normal_force * w.normal;
    for (const auto& a : soft_->applied()) force += a.head<3>();
    if (normal.squaredNorm() > 0) f += force.dot(normal.normalized());
  }
  return f + NormalForce();
}

double Sim::Advance(int n) {
  double sum = 0;
  for (int i = 0; i < n; ++i) sum += Step();
  return n > 0 ? sum / n : 0.0;
}

Snapshot Sim::Save() const {
  Snapshot s;
  s.time = d_->time;
  s.qpos.assign(d_->qpos, d_->qpos + m_->nq);
  s.qvel.assign(d_->qvel, d_->qvel + m_->nv);
  s.act.assign(d_->act, d_->act + m_->na);
  s.warmstart.assign(d_->qacc_warmstart, d_->qacc_warmstart + m_->nv);
  s.xfrc.assign(d_->xfrc_applied, d_->xfrc_applied + 6 * m_->nbody);
  s.qfrc.assign(d_->qfrc_applied, d_->qfrc_applied + m_->nv);
  if (soft_) {
    s.has_soft = true;
    s.soft = soft_->SaveState();
  }
  return s;
}

void Sim::Restore(const Snapshot& s) {
  d_->time = s.time;
  std::copy(s.qpos.begin(), s.qpos.end(), d_->qpos);
  std::copy(s.qvel.begin(), s.qvel.end(), d_->qvel);
  std::copy(s.act.begin(), s.act.end(), d_->act);
  std::copy(s.warmstart.begin(), s.warmstart.end(), d_->qacc_warmstart);
  std::copy(s.xfrc.begin(), s.xfrc.end(), d_->xfrc_applied);
  std::copy(s.qfrc.begin(), s.qfrc.end(), d_->qfrc_applied);
  if (soft_ && s.has_soft) soft_->RestoreState(s.soft);
}

void Sim::Positions(std::vector<double>* out) {
  mj_kinematics(m_, d_);
  out->assign(d_->xpos + 3, d_->xpos + 3 * m_->nbody);
}

bool Sim::Finite() const {
  for (int i = 0; i < m_->nq; ++i)
    if (!std::isfinite(d_->qpos[i])) return false;
  for (int i = 0; i < m_->nv; ++i)
    if (!std::isfinite(d_->qvel[i]) || std::fabs(d_->qvel[i]) > 1e3) return false;
  return true;
}

double PositionError(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size()) / 3;
  if (n == 0) return 0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const double dx = a[3 * i] - b[3 * i], dy = a[3 * i + 1] - b[3 * i + 1],
                 dz = a[3 * i + 2] - b[3 * i + 2];
    sum += std::sqrt(dx * dx + dy * dy + dz * dz);
  }
  return sum / n;
}

bool MakeReference(const SceneSpec& scene, const Setting& setting, double window,
                   Reference* ref, std::string* error) {
  ref->setting = setting;
  ref->window = window;
  ref->states.clear();
  ref->positions.clear();
  ref->force.clear();
  ref->cpu = ref->sim_time = 0;
  auto sim = Sim::Create(scene, setting, error);
  if (!sim) return false;
  if (scene.preroll > 0) {
    // the initial condition: the scene run for `preroll` seconds at 1 ms (Euler), same contact
    Setting pre = setting;
    pre.integrator = Integrator::kEuler;
    pre.dt = 1e-3;
    pre.iterations = pre.tolerance = -1;
    auto p = Sim::Create(scene, pre, error);
    if (!p) return false;
    p->Advance(static_cast<int>(std::lround(scene.preroll / pre.dt)));
    if (!p->Finite()) {
      *error = "scene " + scene.name + ": the pre-roll diverged";
      return false;
    }
    sim->Restore(p->Save());
  }
  const int spw = static_cast<int>(std::lround(window / setting.dt));
  const int nwin = static_cast<int>(std::lround(scene.duration / window));
  std::vector<double> pos;
  ref->states.push_back(sim->Save());
  sim->Positions(&pos);
  ref->positions.push_back(pos);
  ref->force.push_back(0);
  const long w0 = model::WarningCount();
  for (int k = 1; k <= nwin; ++k) {
    const double t0 = ThreadCpuSeconds();
    const double f = sim->Advance(spw);
    ref->cpu += ThreadCpuSeconds() - t0;
    ref->sim_time += spw * setting.dt;
    if (!sim->Finite() || model::WarningCount() != w0) {
      *error = "scene " + scene.name + ": the reference (" + Describe(setting) + ") diverged" +
               (model::WarningCount() != w0 ? std::string(": ") + model::LastWarning() : "");
      return false;
    }
    ref->states.push_back(sim->Save());
    sim->Positions(&pos);
    ref->positions.push_back(pos);
    ref->force.push_back(f);
  }
  return true;
}

PieceResult RunPieces(const SceneSpec& scene, const Setting& setting, const Reference& ref,
                      int restarts, int piece_windows) {
  PieceResult r;
  std::string error;
  auto sim = Sim::Create(scene, setting, &error);
  if (!sim) {
    r.diverged = true;
    r.note = error;
    return r;
  }
  {
    const mjModel* m = sim->m();
    r.iterations = m->opt.iterations;
    r.tolerance = m->opt.tolerance;
    if (setting.contact == Contact::kNative || setting.contact == Contact::kRigid) {
      for (int g = 0; g < m->ngeom && !(m->opt.disableflags & mjDSBL_REFSAFE); ++g) {
        if (!(m->geom_contype[g] || m->geom_conaffinity[g])) continue;
        const double tc = m->geom_solref[mjNREF * g];
        if (tc > 0 && tc < 2 * m->opt.timestep * (1 - 1e-9)) r.refsafe = true;
      }
    }
  }
  const double steps = ref.window / setting.dt;
  const int spw = static_cast<int>(std::lround(steps));
  if (spw < 1 || std::fabs(steps - spw) > 1e-9) {
    r.diverged = true;
    r.note = "the step does not divide the comparison window";
    return r;
  }
  const int nwin = static_cast<int>(ref.states.size()) - 1;
  piece_windows = std::min(piece_windows, nwin);
  restarts = std::max(1, restarts);
  double pos_sum = 0, force_sum = 0;
  int count = 0;
  std::vector<double> pos;
  for (int i = 0; i < restarts; ++i) {
    const int k0 = restarts == 1 ? 0 : static_cast<int>(std::lround(
                                           static_cast<double>(i) * (nwin - piece_windows) /
                                           (restarts - 1)));
    sim->Restore(ref.states[k0]);
    const long w0 = model::WarningCount();
    for (int w = 1; w <= piece_windows; ++w) {
      const double t0 = ThreadCpuSeconds();
      const double f = sim->Advance(spw);
      r.cpu += ThreadCpuSeconds() - t0;
      r.sim_time += spw * setting.dt;
      if (!sim->Finite() || model::WarningCount() != w0) {
        r.diverged = true;
        r.note = model::WarningCount() != w0 ? std::string("MuJoCo: ") + model::LastWarning()
                                           : "non-finite state or speed above 1000 m/s";
        r.pos_error = r.force_error = kInf;
        return r;
      }
      sim->Positions(&pos);
      pos_sum += PositionError(pos, ref.positions[k0 + w]);
      force_sum += std::fabs(f - ref.force[k0 + w]);
      ++count;
    }
  }
  r.pos_error = pos_sum / count;
  r.force_error = force_sum / count;
  return r;
}

}  // namespace ohrp::accuracy
