#include "sim_host/step.h"

namespace ohrp::sim {

PhysicsStep::PhysicsStep(mjModel* m, mjData* d, const Parts& parts)
    : m_(m), d_(d), parts_(parts), fold_(m) {
  const size_t n = parts_.pushes ? parts_.pushes->size() : 0;
  push_on_.assign(n, 0);
  push_changed_.assign(n, 0);
}

bool PhysicsStep::Step(bool sensors) {
  // the pushes on the step about to run, and which of them started or ended
  if (parts_.pushes && !parts_.pushes->empty() && parts_.push_body >= 0) {
    ApplyPushes(*parts_.pushes, m_, d_, parts_.push_body, pushed_);
    const double dt = m_->opt.timestep;
    for (size_t i = 0; i < push_on_.size(); ++i) {
      const char on = PushActiveAt((*parts_.pushes)[i], d_->time, dt) ? 1 : 0;
      push_changed_[i] = on != push_on_[i];
      push_on_[i] = on;
    }
  }
  // the servo's law, the soles' force, the step, the soles' friction state
  if (parts_.servo) parts_.servo->Apply(m_, d_);
  const int flags = m_->opt.disableflags;
  if (!sensors) m_->opt.disableflags |= mjDSBL_SENSOR;
  fold_.Begin(m_, d_);  // Euler's implicit joint damping through M's own factorisation
  if (parts_.soft && !parts_.soft->at_every_stage() && m_->opt.integrator != mjINT_RK4) {
    // split around the contact, so that the kinematics and the mass matrix MuJoCo computes for
    // the step are those the contact uses (RK4 has no split: mj_step integrates it)
    mj_step1(m_, d_);
    parts_.soft->ApplyAfterStep1(m_, d_);
    mj_step2(m_, d_);
  } else {
    if (parts_.soft) parts_.soft->ApplyBeforeStep(m_, d_);
    mj_step(m_, d_);
  }
  fold_.End(m_, d_);
  m_->opt.disableflags = flags;
  if (parts_.soft) parts_.soft->Commit();
  ++steps_;
  // the divergence watch
  return !(parts_.watch && parts_.watch->Check(m_, d_, steps_));
}

}  // namespace ohrp::sim
