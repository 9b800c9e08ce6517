// Joint damping taken implicitly through the mass matrix MuJoCo factorises anyway.
//
// MuJoCo 2.2's Euler step integrates joint damping implicitly: when any dof has damping it
// factorises M + h D a second time (mj_factorI on qH) and solves with it, after the step had
// already factorised M. On HRP-1S that second factorisation and solve are about a tenth of the
// step, spent on a damping of 0.1 N m s/rad against an armature of 12 kg m^2.
//
// The fold gives MuJoCo the same equation with one factorisation: for the step, each damped
// dof's damping d goes into its armature (a + h d; also into dof_M0 for a dof MuJoCo marks
// "simple", whose diagonal mj_crb copies from there) and its force -d v0 (at the step's start
// velocity, as mj_passive computes it) into qfrc_applied, with the damping itself set to 0. Then
//     (M + h D) qacc = f - D v0,   i.e.   M qacc = f - D (v0 + h qacc) = f - D v1,
// exactly MuJoCo's implicit damping (f: every other force), and mj_step2's Euler sees no damping
// and integrates qacc as it is. The one difference is where constraints act (joint limits,
// MuJoCo's contacts): their forces are solved with M + h D, the matrix the step really moves
// with, where MuJoCo solves them with M and then lets the implicit damping change the
// constrained acceleration. The soft soles' apparent inertia is M + h D too, also the matrix
// the step moves with.
//
// End() puts back the model (armature, damping and dof_M0, bit for bit), qfrc_applied (bit for
// bit) and the mass matrix's diagonal (d->qM, to rounding), so that nothing outside the step
// sees the fold: the divergence watch's kinetic energy, the diagnosis's inertias, logs. d->qLD (and
// qLDiagInv, qLDiagSqrtInv) stay the factors of M + h D that the step used; d->qacc is the
// acceleration the step applied (MuJoCo's Euler leaves there the one without the damping's
// implicit part).
//
// Only for the Euler integrator (RK4 and the implicit integrator treat damping their own way:
// Begin does nothing for them) and only with the passive forces' flag as MuJoCo would have it
// (mjDSBL_PASSIVE: no damping force, the armature part still, as mj_Euler does). No allocation
// after construction; not thread-safe on a shared model (it writes the model for the step).
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

namespace ohrp::sim {

class DampingFold {
 public:
  explicit DampingFold(const mjModel* m);

  // Before mj_step (or mj_step1): folds the damping of the dofs that have it. Returns whether
  // it did (Euler and any damped dof); End() must follow the step if it did.
  bool Begin(mjModel* m, mjData* d);
  void End(mjModel* m, mjData* d);

  // the dofs with damping at construction (a dof given damping later is left to MuJoCo)
  const std::vector<int>& dofs() const { return dofs_; }

 private:
  struct Saved {
    double armature = 0, damping = 0, applied = 0, m0 = 0;
  };
  std::vector<int> dofs_;
  std::vector<Saved> saved_;
  double h_ = 0;  // the step the fold was made for
  bool folded_ = false;
};

}  // namespace ohrp::sim
