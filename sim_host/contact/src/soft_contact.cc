#include "contact/soft_contact.h"

#include <algorithm>

#include <Eigen/Geometry>
#include <map>
#include <set>
#include <sstream>
#include <utility>

namespace ohrp::contact {
namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;

Eigen::Isometry3d GeomPose(const mjData* d, int g) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d->geom_xmat + 9 * g);
  T.translation() = Eigen::Map<const Eigen::Vector3d>(d->geom_xpos + 3 * g);
  return T;
}

// Pose of a geom in the model's reference configuration is not needed: environment objects are
// re-posed from mjData at each evaluation (they are static, this is cheap).
bool MakeEnvObject(const mjModel* m, int g, EnvObject* out, std::string* error) {
  const char* raw = mj_id2name(m, mjOBJ_GEOM, g);
  std::string name = raw ? raw : ("geom #" + std::to_string(g));
  const mjtNum* s = m->geom_size + 3 * g;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  switch (m->geom_type[g]) {
    case mjGEOM_PLANE:
      *out = EnvObject::Plane(name, I);
      break;
    case mjGEOM_BOX:
      *out = EnvObject::Box(name, I, Eigen::Vector3d(s[0], s[1], s[2]));
      break;
    case mjGEOM_SPHERE:
      *out = EnvObject::Sphere(name, I, s[0]);
      break;
    case mjGEOM_CAPSULE:
      *out = EnvObject::Capsule(name, I, s[0], s[1]);
      break;
    case mjGEOM_CYLINDER:
      *out = EnvObject::Cylinder(name, I, s[0], s[1]);
      break;
    case mjGEOM_MESH: {
      const int mesh = m->geom_dataid[g];
      const int adr = m->mesh_graphadr[mesh];
      if (adr < 0) {
        *error = "environment geom '" + name +
                 "' is a mesh without a convex hull in the model (MuJoCo computes it when the "
                 "mesh has at least 4 non-coplanar vertices); give it a volume";
        return false;
      }
      const int* graph = m->mesh_graph + adr;
      const int numvert = graph[0];
      const int numface = graph[1];
      const int* vert_globalid = graph + 2 + numvert;
      const int* face_globalid = graph + 2 + 3 * numvert + 3 * numface;
      const float* vert = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
      std::vector<Eigen::Vector3d> verts;
      std::map<int, int> local;
      for (int i = 0; i < numvert; ++i) {
        const int gid = vert_globalid[i];
        local[gid] = i;
        verts.emplace_back(vert[3 * gid], vert[3 * gid + 1], vert[3 * gid + 2]);
      }
      std::vector<int> tris;
      for (int f = 0; f < 3 * numface; ++f) tris.push_back(local.at(face_globalid[f]));
      *out = EnvObject::Convex(name, I, std::move(verts), tris);
      break;
    }
    case mjGEOM_HFIELD: {
      const int h = m->geom_dataid[g];
      const int nrow = m->hfield_nrow[h], ncol = m->hfield_ncol[h];
      const mjtNum* hs = m->hfield_size + 4 * h;
      if (nrow < 2 || ncol < 2) {
        *error = "environment geom '" + name + "' is a heightfield with fewer than 2 x 2 samples";
        return false;
      }
      std::vector<double> z(static_cast<size_t>(nrow) * ncol);
      for (size_t i = 0; i < z.size(); ++i) z[i] = hs[2] * m->hfield_data[m->hfield_adr[h] + i];
      *out = EnvObject::HeightField(name, I, nrow, ncol, hs[0], hs[1], hs[3], std::move(z));
      break;
    }
    default:
      *error = "environment geom '" + name + "' has a type the soft-foot contact does not handle";
      return false;
  }
  out->geom_id = g;
  return true;
}

}  // namespace

SoftFootContact::SoftFootContact(ContactGeometry geometry, const SoftContactParams& params)
    : geometry_(std::move(geometry)), params_(params) {}

std::unique_ptr<SoftFootContact> SoftFootContact::Create(
    const mjModel* m, const std::vector<std::string>& sole_geoms,
    const std::vector<std::string>& env_geoms, const SoftContactParams& params, double mass_scale,
    std::string* error) {
  std::string err;
  // RK4 evaluates the law at its stages (explicit); the other integrators take the implicit step
  const StepScheme scheme =
      m->opt.integrator == mjINT_RK4 ? StepScheme::kExplicit : StepScheme::kImplicit;
  if (!Validate(params, m->opt.timestep, mass_scale, &err, scheme)) {
    *error = "soft-foot contact parameters refused:\n" + err;
    return nullptr;
  }
  if (sole_geoms.empty()) {
    *error = "soft-foot contact: no sole geoms given; name the soles' box geoms (e.g. RLEG_SOLE)";
    return nullptr;
  }
  std::vector<int> soles;
  for (const std::string& s : sole_geoms) {
    const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str());
    if (g < 0) {
      *error = "soft-foot contact: sole geom '" + s + "' is not in the model (a sole needs a box "
               "geom)";
      return nullptr;
    }
    if (m->geom_type[g] != mjGEOM_BOX) {
      *error = "soft-foot contact: sole geom '" + s + "' is not a box; the model samples the "
               "bottom face of a box sole";
      return nullptr;
    }
    soles.push_back(g);
  }
  std::set<int> sole_set(soles.begin(), soles.end());
  std::vector<int> env_ids;
  if (env_geoms.empty()) {
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] == 0 && !sole_set.count(g)) env_ids.push_back(g);
    }
  } else {
    for (const std::string& s : env_geoms) {
      const int g = mj_name2id(m, mjOBJ_GEOM, s.c_str());
      if (g < 0) {
        *error = "soft-foot contact: environment geom '" + s + "' is not in the model";
        return nullptr;
      }
      if (m->body_weldid[m->geom_bodyid[g]] != 0) {
        *error = "soft-foot contact: environment geom '" + s + "' moves (its body is not welded "
                 "to the world); only a static environment is supported";
        return nullptr;
      }
      env_ids.push_back(g);
    }
  }
  if (env_ids.empty()) {
    *error = "soft-foot contact: no environment geoms to touch (the world body has no geoms)";
    return nullptr;
  }
  std::vector<EnvObject> env;
  for (int g : env_ids) {
    EnvObject o;
    if (!MakeEnvObject(m, g, &o, error)) return nullptr;
    env.push_back(std::move(o));
  }
  std::unique_ptr<SoftFootContact> c(
      new SoftFootContact(ContactGeometry(std::move(env), params.margin), params));
  for (int g : soles) {
    const Eigen::Vector3d half(m->geom_size[3 * g], m->geom_size[3 * g + 1],
                               m->geom_size[3 * g + 2]);
    c->sole_geom_.push_back(g);
    c->sole_half_.push_back(half);
    c->grid_.push_back(MakeGrid(half, params.grid_x, params.grid_y));
    c->anchors_.emplace_back(c->grid_.back().size());
  }
  if (scheme == StepScheme::kImplicit) c->impact_note_ = ImpactNote(params, m->opt.timestep, mass_scale);
  c->proposed_ = c->anchors_;
  c->scratch_ = c->anchors_;
  c->wrenches_.resize(soles.size());
  // the bodies that carry soles, each once, with what Apply() has added to them (none yet)
  for (int g : soles) {
    const int b = m->geom_bodyid[g];
    if (std::find(c->bodies_.begin(), c->bodies_.end(), b) == c->bodies_.end())
      c->bodies_.push_back(b);
  }
  c->applied_.assign(c->bodies_.size(), Vec6::Zero());
  c->AllocateImplicit(m);
  return c;
}

void SoftFootContact::UpdateKinematics(const mjModel* m, mjData* d) {
  mj_kinematics(m, d);
  mj_comPos(m, d);
  mj_comVel(m, d);
}

const std::vector<SoleWrench>& SoftFootContact::Evaluate(const mjModel* m, const mjData* d,
                                                         bool with_reach) {
  for (EnvObject& o : geometry_.env()) o.pose = GeomPose(d, o.geom_id);
  const double h = m->opt.timestep;
  const double g_norm = mju_norm3(m->opt.gravity);
  for (size_t s = 0; s < sole_geom_.size(); ++s) {
    const int g = sole_geom_[s];
    SoleBox sole{GeomPose(d, g), sole_half_[s]};
    mjtNum vel[6];
    mj_objectVelocity(m, d, mjOBJ_GEOM, g, vel, 0);
    SoleTwist twist;
    twist.angular = Eigen::Vector3d(vel[0], vel[1], vel[2]);
    twist.linear = Eigen::Vector3d(vel[3], vel[4], vel[5]);
    // the implicit step also wants the points that may enter within a step either side: a
    // bound of how far a point moves in two steps at this speed, plus what gravity adds
    const double reach =
        with_reach ? 2 * h * (twist.linear.norm() + twist.angular.norm() * sole_half_[s].norm()) +
                         4 * h * h * g_norm
                   : 0.0;
    geometry_.Find(sole, grid_[s], &points_, reach);
    ComputeWrench(params_, sole, twist, grid_[s], points_, anchors_[s], &scratch_[s],
                  &wrenches_[s]);
  }
  if (!proposed_valid_) {
    proposed_.swap(scratch_);
    proposed_valid_ = true;
  }
  return wrenches_;
}

void SoftFootContact::Apply(const mjModel* m, mjData* d) {
  // per sole body: the new wrench about its centre of mass, replacing what was added last time
  for (size_t k = 0; k < bodies_.size(); ++k) {
    const int b = bodies_[k];
    const Eigen::Vector3d com = Eigen::Map<const Eigen::Vector3d>(d->xipos + 3 * b);
    Vec6 now = Vec6::Zero();
    for (size_t s = 0; s < sole_geom_.size(); ++s) {
      const SoleWrench& w = wrenches_[s];
      if (!w.in_contact || m->geom_bodyid[sole_geom_[s]] != b) continue;
      now.head<3>() += w.force;
      now.tail<3>() += w.torque + (w.point - com).cross(w.force);
    }
    for (int i = 0; i < 6; ++i) d->xfrc_applied[6 * b + i] += now[i] - applied_[k][i];
    applied_[k] = now;
  }
}

void SoftFootContact::ApplyBeforeStep(const mjModel* m, mjData* d) {
  if (at_every_stage_) return;  // mj_step's mj_forward evaluates it (see EvaluateAtEveryStage)
  UpdateKinematics(m, d);
  Evaluate(m, d, implicit_);
  if (implicit_) {
    ApplyImplicit(m, d, /*mass_factored=*/false);
  } else {
    Apply(m, d);
  }
}

void SoftFootContact::ApplyAfterStep1(const mjModel* m, mjData* d) {
  if (at_every_stage_) return;
  Evaluate(m, d, implicit_);
  if (implicit_) {
    ApplyImplicit(m, d, /*mass_factored=*/true);
  } else {
    Apply(m, d);
  }
}

void SoftFootContact::Commit() {
  if (!proposed_valid_) return;
  anchors_.swap(proposed_);
  proposed_valid_ = false;
}

bool SoftFootContact::RestoreState(const State& state) {
  if (state.anchors.size() != anchors_.size() || state.applied.size() != applied_.size())
    return false;
  for (size_t s = 0; s < anchors_.size(); ++s) {
    if (state.anchors[s].size() != anchors_[s].size()) return false;
  }
  for (size_t s = 0; s < anchors_.size(); ++s) {
    std::copy(state.anchors[s].begin(), state.anchors[s].end(), anchors_[s].begin());
  }
  std::copy(state.applied.begin(), state.applied.end(), applied_.begin());
  proposed_valid_ = false;
  return true;
}

namespace {
// the contact evaluated from mjcb_control, and the callback that was there before it
SoftFootContact* g_stage_contact = nullptr;
mjfGeneric g_previous_control = nullptr;

void StageControl(const mjModel* m, mjData* d) {
  if (g_previous_control) g_previous_control(m, d);
  if (g_stage_contact) {
    g_stage_contact->Evaluate(m, d);  // kinematics and com velocities are current here
    g_stage_contact->Apply(m, d);
  }
}
}  // namespace

bool SoftFootContact::EvaluateAtEveryStage(bool on, std::string* error) {
  if (on == at_every_stage_) return true;
  if (on) {
    if (g_stage_contact) {
      if (error) *error = "another soft-foot contact already evaluates at every stage (mjcb_control is process-wide)";
      return false;
    }
    g_previous_control = mjcb_control;
    g_stage_contact = this;
    mjcb_control = StageControl;
  } else {
    mjcb_control = g_previous_control;
    g_previous_control = nullptr;
    g_stage_contact = nullptr;
  }
  at_every_stage_ = on;
  return true;
}

SoftFootContact::~SoftFootContact() { EvaluateAtEveryStage(false); }

void SoftFootContact::Remove(mjData* d) {
  for (size_t k = 0; k < bodies_.size(); ++k) {
    for (int i = 0; i < 6; ++i) d->xfrc_applied[6 * bodies_[k] + i] -= applied_[k][i];
    applied_[k].setZero();
  }
}

}  // namespace ohrp::contact
