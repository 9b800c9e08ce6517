// The actuator that drives one joint, as MuJoCo 2.2.2 computes it, and its inverse: the servo
// and the segment speak joint torques; this turns the torque the servo wants into the control
// MuJoCo needs, whatever the model's author wrote (<motor> with any gear, <position>,
// <velocity>, <general> with a fixed gain and an affine bias).
//
// MuJoCo's law for an actuator with a joint transmission, no activation dynamics, a fixed gain
// and no or an affine bias (engine_forward.c, mj_fwdActuation; engine_core_smooth.c,
// mj_transmission):
//   actuator length   L = gear q                 [rad or m, times gear]
//   actuator velocity V = gear dq
//   ctrl clamped to ctrlrange (when ctrllimited)
//   force  f = gain ctrl + b0 + b1 L + b2 V,  clamped to forcerange (when forcelimited)
//   joint torque tau = gear f                    [N m or N]
// <motor>: gain 1, no bias. <position kp>: gain kp, bias (0, -kp, 0). <velocity kv>: gain kv,
// bias (0, 0, -kv). <general>: as written. So a torque tau at state (q, dq) needs
//   ctrl = (tau / gear - b0 - b1 gear q - b2 gear dq) / gain,
// exact at the state the servo reads (the one mj_step's forward pass sees); the RK4 stages and
// the implicit integrator's velocity derivative see other states.
#pragma once

#include <mujoco/mujoco.h>

#include <string>

namespace ohrp::model {

enum class ActuatorKind { kMotor, kPosition, kVelocity, kGeneral };

// "motor", "position", "velocity" or "general".
const char* ActuatorKindName(ActuatorKind kind);

struct ActuatorLaw {
  ActuatorKind kind = ActuatorKind::kMotor;
  double gear = 1;                          // gear[0] [-]
  double gain = 1;                          // gainprm[0], never 0
  double bias[3] = {0, 0, 0};               // biasprm[0..2]; 0 when biastype is none
  bool ctrl_limited = false;
  double ctrl_min = 0, ctrl_max = 0;        // ctrlrange (when ctrl_limited)
  bool force_limited = false;
  double force_min = 0, force_max = 0;      // forcerange (when force_limited) [actuator force]

  // The control that gives the joint torque `tau` [N m or N] at joint position `q` and velocity
  // `dq`, clamped to what the actuator accepts. `*clamped` is set when ctrlrange or forcerange
  // stops the joint short of `tau`. No allocation.
  double ControlFor(double tau, double q, double dq, bool* clamped) const noexcept;

  // The joint torque that control `ctrl` gives at (q, dq), ctrlrange and forcerange applied:
  // MuJoCo's forward law. No allocation.
  double TorqueFor(double ctrl, double q, double dq) const noexcept;

  // The largest |joint torque| the actuator gives whatever the state [N m or N]: from
  // ctrlrange when the force does not depend on the state, from forcerange, else `unlimited`.
  double TorqueLimit(double unlimited) const noexcept;

  // The joint stiffness and damping of the servo the author built into the actuator:
  // -gear^2 b1 [N m/rad] when it is a position servo (gain = -b1: ctrl is a target, a
  // <position kp> or its <general> equivalent), else 0; -gear^2 b2 [N m s/rad] when b2 < 0
  // (a <position kv>, a <velocity kv>), else 0.
  double Stiffness() const noexcept;
  double Damping() const noexcept;

  // One line for `sim_host --explain`: the type, gear, gain and bias, the ranges, and the
  // mapping used (e.g. "position kp=100 gear=1: ctrl = (tau/1 + 100 q)/100").
  std::string Describe() const;
};

// Reads the law of actuator `a`. Returns false with `*error` naming the actuator, what it has
// and what would work when the law cannot be inverted: a transmission other than a hinge or
// slide joint, activation dynamics (dyntype), a gain that is not fixed or is 0, a bias that is
// not affine.
bool ReadActuatorLaw(const mjModel* m, int a, ActuatorLaw* law, std::string* error);

}  // namespace ohrp::model
