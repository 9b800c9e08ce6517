// ohrp identify --joints --model: the estimates turned into the model's joint parameters
// (identify/joints.h, robot_model/joint_params.h).
#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "identify/joints.h"
#include "robot_model/model.h"

namespace ohrp::identify {
namespace {

// The joint's inertia about its axis from the model in the excitation's posture (the keyframe,
// the joint at its mean logged position), its armature left out: the links' share of the
// identified total. The mass matrix's diagonal is the subtree's inertia about the axis, whatever
// the base does.
bool LinkInertia(model::Scene* scene, const JointLog& log, double* link, double* armature,
                 std::string* error) {
  mjModel* m = scene->m();
  mjData* d = scene->d();
  const int j = mj_name2id(m, mjOBJ_JOINT, log.joint.c_str());
  if (j < 0 || (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE)) {
    *error = log.joint + ": the model has no hinge or slide of that name";
    return false;
  }
  double mean = 0;
  for (double q : log.q) mean += q;
  d->qpos[m->jnt_qposadr[j]] = mean / static_cast<double>(log.q.size());
  mj_forward(m, d);
  const int dof = m->jnt_dofadr[j];
  std::vector<double> full(static_cast<size_t>(m->nv) * m->nv);
  mj_fullM(m, full.data(), d->qM);
  *armature = m->dof_armature[dof];
  *link = full[static_cast<size_t>(dof) * m->nv + dof] - *armature;
  return true;
}

}  // namespace

bool JointParamsFromEstimates(const std::vector<JointLog>& logs,
                              const std::vector<JointEstimate>& estimates,
                              const JointModel& model_in, std::vector<model::JointParams>* out,
                              std::vector<std::string>* warnings, std::string* error) {
  auto scene = model::Scene::Load(model_in.model, error);
  if (!scene) return false;
  out->clear();
  for (size_t i = 0; i < estimates.size(); ++i) {
    if (!scene->Reset(model_in.keyframe, error)) return false;
    const JointEstimate& e = estimates[i];
    double link = 0, armature = 0;
    if (!LinkInertia(scene.get(), logs[i], &link, &armature, error)) return false;
    model::JointParams p;
    p.joint = e.joint;
    p.armature = e.inertia - link;
    p.damping = e.viscous;
    p.frictionloss = e.coulomb;
    // the servo's lag less the simulator's own cycle (a command reaches sim_host's servo one
    // cycle after the sensors it answers): the actuator's delay to simulate
    if (e.lag_cycles > 1) p.delay = (e.lag_cycles - 1) * e.period;
    std::ostringstream note;
    note.precision(3);
    note << "I " << e.inertia << " +- " << e.inertia_se << " less the links' " << link
         << " (model armature " << armature << "); b +- " << e.viscous_se << ", c +- "
         << e.coulomb_se << "; lag " << e.lag_cycles << " cycles";
    p.note = note.str();
    // a negative value is no parameter: the fit or the model is wrong there; kept out, said
    auto keep = [&](const char* key, double* v) {
      if (*v >= 0) return;
      std::ostringstream w;
      w << e.joint << ": the identified " << key << " is " << *v
        << " (negative): the model's value is kept";
      warnings->push_back(w.str());
      *v = NAN;
    };
    keep("armature (the total inertia less the links')", &p.armature);
    keep("viscous friction", &p.damping);
    keep("Coulomb friction", &p.frictionloss);
    out->push_back(p);
  }
  return true;
}

}  // namespace ohrp::identify
