// The run-time divergence watch: set-up, energy, the per-step check (see divergence.h; the
// diagnostic is in divergence_diagnosis.cc).
#include "sim_host/divergence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "divergence_internal.h"

namespace ohrp::sim {

using namespace divergence_internal;  // NOLINT: the watch's own helpers

const char* DivergenceKindName(DivergenceKind kind) {
  switch (kind) {
    case DivergenceKind::kNone: return "none";
    case DivergenceKind::kMujocoReset: return "mujoco_reset";
    case DivergenceKind::kNonFinite: return "non_finite";
    case DivergenceKind::kRunaway: return "runaway";
    case DivergenceKind::kEnergy: return "energy";
  }
  return "?";
}

//---------------- set-up ----------------

DivergenceWatch::DivergenceWatch(const mjModel* m, const WatchLimits& limits)
    : limits_(limits),
      passive_(m->nbody, 0),
      last_qpos_(m->nq, 0.0),
      last_qvel_(m->nv, 0.0),
      last_qacc_(m->nv, 0.0) {
  double mass = 0;
  for (int b = 1; b < m->nbody; ++b) mass += m->body_mass[b];
  const double g = std::sqrt(m->opt.gravity[0] * m->opt.gravity[0] +
                             m->opt.gravity[1] * m->opt.gravity[1] +
                             m->opt.gravity[2] * m->opt.gravity[2]);
  margin_ = mass * std::max(g, 1.0) * limits_.energy_height;
}

void DivergenceWatch::SetPassiveBodies(const std::vector<int>& bodies) {
  for (int b : bodies)
    if (b >= 0 && b < static_cast<int>(passive_.size())) passive_[b] = 1;
}

void DivergenceWatch::Start(const mjModel* m, mjData* d) {
  mj_forward(m, d);
  for (int w = 0; w < mjNWARNING; ++w) baseline_[w] = d->warning[w].number;
  std::copy(d->qpos, d->qpos + m->nq, last_qpos_.begin());
  std::copy(d->qvel, d->qvel + m->nv, last_qvel_.begin());
  std::copy(d->qacc, d->qacc + m->nv, last_qacc_.begin());
  energy0_ = energy_ = Energy(m, d);
  work_ = 0;
  max_excess_ = 0;
  last_time_ = d->time;
  kind_ = DivergenceKind::kNone;
  index_ = warning_ = -1;
}

namespace {

// Potential energy of the state in `d` as MuJoCo defines it (gravity on every body's centre of
// mass, joint springs about qpos_spring, tendon springs about their spring length), computed
// here because MuJoCo 2.2's mj_energyPos leaves 0 unless the scene enables the `energy` flag.
double PotentialEnergy(const mjModel* m, const mjData* d) {
  double e = 0;
  // gravity: -sum_b m_b g . p_W(com of b)
  if (!(m->opt.disableflags & mjDSBL_GRAVITY)) {
    const double* g = m->opt.gravity;
    for (int b = 1; b < m->nbody; ++b) {
      const double* p = d->xipos + 3 * b;
      e -= m->body_mass[b] * (g[0] * p[0] + g[1] * p[1] + g[2] * p[2]);
    }
  }
  if (m->opt.disableflags & mjDSBL_PASSIVE) return e;  // springs are passive forces
  // joint springs: 0.5 k |q - q_spring|^2, rotations as the angle of the quaternion difference
  for (int j = 0; j < m->njnt; ++j) {
    const double k = m->jnt_stiffness[j];
    if (k == 0) continue;
    const int a = m->jnt_qposadr[j];
    const double* q = d->qpos + a;
    const double* q0 = m->qpos_spring + a;
    double sq = 0;
    int rot = -1;  // qpos address of a quaternion, if any
    switch (m->jnt_type[j]) {
      case mjJNT_FREE:
        for (int i = 0; i < 3; ++i) sq += (q[i] - q0[i]) * (q[i] - q0[i]);
        rot = a + 3;
        break;
      case mjJNT_BALL:
        rot = a;
        break;
      default:  // hinge, slide
        sq = (q[0] - q0[0]) * (q[0] - q0[0]);
    }
    if (rot >= 0) {
      double quat[4], w[3];
      for (int i = 0; i < 4; ++i) quat[i] = d->qpos[rot + i];
      mju_normalize4(quat);
      mju_subQuat(w, quat, m->qpos_spring + rot);
      sq += w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    }
    e += 0.5 * k * sq;
  }
  // tendon springs: 0.5 k (L - L_spring)^2
  for (int t = 0; t < m->ntendon; ++t) {
    const double k = m->tendon_stiffness[t];
    if (k == 0) continue;
    const double dl = d->ten_length[t] - m->tendon_lengthspring[t];
    e += 0.5 * k * dl * dl;
  }
  return e;
}

// 1/2 v^T M v on MuJoCo's sparse mass matrix qM (per dof its diagonal at dof_Madr, then the
// entries of its ancestors up the dof tree): mj_mulM and a dot product in one pass, without
// their function calls per dof (the watch's check: 8.7k -> 6.3k instructions per HRP-1S step)
double KineticEnergy(const mjModel* m, const mjData* d) {
  double e = 0;
  for (int i = 0; i < m->nv; ++i) {
    int adr = m->dof_Madr[i];
    const double vi = d->qvel[i];
    double coupled = 0;  // sum over the ancestors j of M_ij v_j, each pair counted once
    for (int j = m->dof_parentid[i]; j >= 0; j = m->dof_parentid[j])
      coupled += d->qM[++adr] * d->qvel[j];
    e += vi * (0.5 * d->qM[m->dof_Madr[i]] * vi + coupled);
  }
  return e;
}

}  // namespace

double DivergenceWatch::Energy(const mjModel* m, mjData* d) {
  // after mj_step the kinematics (xipos) and the mass matrix are those of the state at the
  // start of the step, qpos and qvel the new ones: E of the new state up to a positional lag,
  // about M |g| |v| dt (0.1 J for 1 kg falling at 10 m/s at 1 ms), far below the margin. Using
  // the new velocity catches a blow-up in the step it happens, while the contact that caused
  // it is still in place for the diagnostic.
  d->energy[0] = PotentialEnergy(m, d);
  const double kinetic = KineticEnergy(m, d);
  d->energy[1] = kinetic;
  return d->energy[0] + kinetic;
}

//---------------- the per-step check ----------------

void DivergenceWatch::Latch(DivergenceKind kind, uint64_t step, int index) {
  kind_ = kind;
  step_ = step;
  time_ = last_time_;
  index_ = index;
}

bool DivergenceWatch::Check(const mjModel* m, mjData* d, uint64_t step) {
  if (kind_ != DivergenceKind::kNone) return true;

  // 1. MuJoCo found a bad number and reset the state
  for (int w : kResetWarnings) {
    if (d->warning[w].number != baseline_[w]) {
      warning_ = w;
      Latch(DivergenceKind::kMujocoReset, step, d->warning[w].lastinfo);
      return true;
    }
  }
  // 2. non-finite or runaway state
  for (int i = 0; i < m->nq; ++i) {
    if (!std::isfinite(d->qpos[i])) {
      // report the dof of the joint owning this qpos entry
      int dof = -1;
      for (int j = 0; j < m->njnt; ++j)
        if (m->jnt_qposadr[j] <= i) dof = m->jnt_dofadr[j];
      Latch(DivergenceKind::kNonFinite, step, dof);
      return true;
    }
  }
  for (int i = 0; i < m->nv; ++i) {
    const double v = d->qvel[i];
    if (!std::isfinite(v) || !std::isfinite(d->qacc[i])) {
      Latch(DivergenceKind::kNonFinite, step, i);
      return true;
    }
    if (std::fabs(v) > limits_.max_speed) {
      Latch(DivergenceKind::kRunaway, step, i);
      return true;
    }
  }
  // a controller's non-finite control: MuJoCo clamps +-inf of a limited actuator silently
  for (int i = 0; i < m->nu; ++i) {
    if (!std::isfinite(d->ctrl[i])) {
      warning_ = mjWARN_BADCTRL;
      Latch(DivergenceKind::kNonFinite, step, i);
      return true;
    }
  }
  // 3. energy against the work of the sources over this step
  const double dt = m->opt.timestep;
  double power = 0;
  for (int i = 0; i < m->nv; ++i) {
    power += std::max(0.0, d->qfrc_actuator[i] * d->qvel[i]);
    power += std::max(0.0, d->qfrc_applied[i] * d->qvel[i]);
  }
  for (int b = 1; b < m->nbody; ++b) {
    if (passive_[b]) continue;
    const double* f = d->xfrc_applied + 6 * b;
    if (f[0] == 0 && f[1] == 0 && f[2] == 0 && f[3] == 0 && f[4] == 0 && f[5] == 0) continue;
    double v[3], w[3];
    BodyVelocity(m, d, b, v, w);
    power += std::max(0.0, f[0] * v[0] + f[1] * v[1] + f[2] * v[2] +
                               f[3] * w[0] + f[4] * w[1] + f[5] * w[2]);
  }
  work_ += power * dt;
  energy_ = Energy(m, d);
  const double excess = energy_ - energy0_ - work_;
  if (excess > max_excess_) max_excess_ = excess;
  if (!(excess <= margin_)) {  // also catches a NaN energy
    Latch(DivergenceKind::kEnergy, step, -1);
    return true;
  }
  // keep the last good state for the diagnostic
  std::memcpy(last_qpos_.data(), d->qpos, sizeof(double) * m->nq);
  std::memcpy(last_qvel_.data(), d->qvel, sizeof(double) * m->nv);
  std::memcpy(last_qacc_.data(), d->qacc, sizeof(double) * m->nv);
  last_time_ = d->time;
  return false;
}

}  // namespace ohrp::sim
