#include "sim_host/damping_fold.h"

namespace ohrp::sim {

DampingFold::DampingFold(const mjModel* m) {
  for (int i = 0; i < m->nv; ++i)
    if (m->dof_damping[i] > 0) dofs_.push_back(i);
  saved_.resize(dofs_.size());
}

bool DampingFold::Begin(mjModel* m, mjData* d) {
  folded_ = false;
  if (m->opt.integrator != mjINT_EULER || dofs_.empty()) return false;
  h_ = m->opt.timestep;
  const bool passive = !(m->opt.disableflags & mjDSBL_PASSIVE);
  for (size_t k = 0; k < dofs_.size(); ++k) {
    const int i = dofs_[k];
    Saved& s = saved_[k];
    s.armature = m->dof_armature[i];
    s.damping = m->dof_damping[i];
    s.applied = d->qfrc_applied[i];
    s.m0 = m->dof_M0[i];
    m->dof_armature[i] = s.armature + h_ * s.damping;
    // a "simple" dof's diagonal is not computed: mj_crb copies it from dof_M0
    if (m->dof_simplenum[i]) m->dof_M0[i] = s.m0 + h_ * s.damping;
    m->dof_damping[i] = 0;
    if (passive) d->qfrc_applied[i] = s.applied - s.damping * d->qvel[i];
  }
  folded_ = true;
  return true;
}

void DampingFold::End(mjModel* m, mjData* d) {
  if (!folded_) return;
  for (size_t k = 0; k < dofs_.size(); ++k) {
    const int i = dofs_[k];
    const Saved& s = saved_[k];
    m->dof_armature[i] = s.armature;
    m->dof_damping[i] = s.damping;
    m->dof_M0[i] = s.m0;
    d->qfrc_applied[i] = s.applied;
    d->qM[m->dof_Madr[i]] -= h_ * s.damping;
  }
  folded_ = false;
}

}  // namespace ohrp::sim
