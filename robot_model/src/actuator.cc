// Actuator laws and their inverse (see actuator.h).
#include "robot_model/actuator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::model {
namespace {

std::string ActuatorName(const mjModel* m, int a) {
  const char* n = mj_id2name(m, mjOBJ_ACTUATOR, a);
  return n && n[0] ? "actuator '" + std::string(n) + "'" : "actuator #" + std::to_string(a);
}

// which element the author most likely wrote, from the compiled gain and bias
ActuatorKind Classify(const ActuatorLaw& l, bool affine) {
  if (!affine) return l.gain == 1.0 ? ActuatorKind::kMotor : ActuatorKind::kGeneral;
  if (l.bias[0] == 0 && l.bias[2] == 0 && l.bias[1] == -l.gain) return ActuatorKind::kPosition;
  if (l.bias[0] == 0 && l.bias[1] == 0 && l.bias[2] == -l.gain) return ActuatorKind::kVelocity;
  return ActuatorKind::kGeneral;
}

// a clamp that changed the value by more than rounding (a torque at exactly the limit, divided
// by the gear, may land an ulp beyond ctrlrange)
bool Beyond(double wanted, double kept) {
  return std::fabs(wanted - kept) > 1e-9 * (1.0 + std::fabs(kept));
}

}  // namespace

const char* ActuatorKindName(ActuatorKind kind) {
  switch (kind) {
    case ActuatorKind::kMotor: return "motor";
    case ActuatorKind::kPosition: return "position";
    case ActuatorKind::kVelocity: return "velocity";
    case ActuatorKind::kGeneral: return "general";
  }
  return "?";
}

//---------------- the law and its inverse ----------------

double ActuatorLaw::ControlFor(double tau, double q, double dq, bool* clamped) const noexcept {
  // the actuator force wanted, within forcerange
  double force = tau / gear;
  bool cut = false;
  if (force_limited) {
    const double kept = std::clamp(force, force_min, force_max);
    cut = Beyond(force, kept);
    force = kept;
  }
  // invert the affine law at this state, then keep ctrl within ctrlrange
  const double state_force = bias[0] + bias[1] * gear * q + bias[2] * gear * dq;
  double ctrl = (force - state_force) / gain;
  if (ctrl_limited) {
    const double kept = std::clamp(ctrl, ctrl_min, ctrl_max);
    cut = cut || Beyond(ctrl, kept);
    ctrl = kept;
  }
  *clamped = cut;
  return ctrl;
}

double ActuatorLaw::TorqueFor(double ctrl, double q, double dq) const noexcept {
  if (ctrl_limited) ctrl = std::clamp(ctrl, ctrl_min, ctrl_max);
  double force = gain * ctrl + bias[0] + bias[1] * gear * q + bias[2] * gear * dq;
  if (force_limited) force = std::clamp(force, force_min, force_max);
  return gear * force;
}

double ActuatorLaw::TorqueLimit(double unlimited) const noexcept {
  double lo = -unlimited, hi = unlimited;  // actuator force bounds
  bool bounded = false;
  // a force that does not depend on the state is bounded by ctrlrange
  if (ctrl_limited && bias[1] == 0 && bias[2] == 0) {
    const double a = gain * ctrl_min + bias[0], b = gain * ctrl_max + bias[0];
    lo = std::min(a, b);
    hi = std::max(a, b);
    bounded = true;
  }
  if (force_limited) {
    lo = bounded ? std::max(lo, force_min) : force_min;
    hi = bounded ? std::min(hi, force_max) : force_max;
    bounded = true;
  }
  if (!bounded) return unlimited;
  return std::fabs(gear) * std::max(std::fabs(lo), std::fabs(hi));
}

double ActuatorLaw::Stiffness() const noexcept {
  // a position servo: ctrl is the target of the actuator length (gain = -b1)
  const bool servo = bias[1] < 0 && std::fabs(gain + bias[1]) <= 1e-9 * gain;
  return servo ? -gear * gear * bias[1] : 0.0;
}

double ActuatorLaw::Damping() const noexcept {
  return bias[2] < 0 ? -gear * gear * bias[2] : 0.0;
}

std::string ActuatorLaw::Describe() const {
  char buf[384];
  int n = 0;
  switch (kind) {
    case ActuatorKind::kMotor:
      n = std::snprintf(buf, sizeof buf, "motor gear=%g: ctrl = tau/%g", gear, gear);
      break;
    case ActuatorKind::kPosition:
      n = std::snprintf(buf, sizeof buf, "position kp=%g gear=%g: ctrl = (tau/%g + %g*%g q)/%g",
                        gain, gear, gear, gain, gear, gain);
      break;
    case ActuatorKind::kVelocity:
      n = std::snprintf(buf, sizeof buf, "velocity kv=%g gear=%g: ctrl = (tau/%g + %g*%g dq)/%g",
                        gain, gear, gear, gain, gear, gain);
      break;
    case ActuatorKind::kGeneral:
      n = std::snprintf(buf, sizeof buf,
                        "general gain=%g bias=(%g, %g, %g) gear=%g: ctrl = (tau/%g - %g - %g*%g q "
                        "- %g*%g dq)/%g",
                        gain, bias[0], bias[1], bias[2], gear, gear, bias[0], bias[1], gear,
                        bias[2], gear, gain);
      break;
  }
  std::string s(buf, static_cast<size_t>(std::max(n, 0)));
  if (ctrl_limited) {
    std::snprintf(buf, sizeof buf, ", ctrl in [%g, %g]", ctrl_min, ctrl_max);
    s += buf;
  }
  if (force_limited) {
    std::snprintf(buf, sizeof buf, ", force in [%g, %g]", force_min, force_max);
    s += buf;
  }
  return s;
}

//---------------- reading the model ----------------

bool ReadActuatorLaw(const mjModel* m, int a, ActuatorLaw* law, std::string* error) {
  *law = ActuatorLaw{};
  const std::string name = ActuatorName(m, a);
  const int trn = m->actuator_trntype[a];
  if (trn != mjTRN_JOINT && trn != mjTRN_JOINTINPARENT) {
    *error = name + " does not act on a joint (tendon, site or slider-crank transmission): the "
                    "segment carries joint actuators only; drive the joint itself (joint=\"...\")";
    return false;
  }
  const int joint = m->actuator_trnid[2 * a];
  const int jtype = m->jnt_type[joint];
  if (jtype != mjJNT_HINGE && jtype != mjJNT_SLIDE) {
    *error = name + " drives a ball or free joint: only hinge and slide joints can be commanded";
    return false;
  }
  if (m->actuator_dyntype[a] != mjDYN_NONE) {
    *error = name + " has activation dynamics (dyntype " + std::to_string(m->actuator_dyntype[a]) +
             "): the segment's torques need an actuator without them (dyntype=\"none\", e.g. "
             "<motor>, <position>, <velocity>)";
    return false;
  }
  if (m->actuator_gaintype[a] != mjGAIN_FIXED) {
    *error = name + " has a gain that is not fixed: use gaintype=\"fixed\"";
    return false;
  }
  const int bias = m->actuator_biastype[a];
  if (bias != mjBIAS_NONE && bias != mjBIAS_AFFINE) {
    *error = name + " has a bias that is not affine: use biastype=\"none\" or \"affine\"";
    return false;
  }
  law->gear = m->actuator_gear[6 * a];
  law->gain = m->actuator_gainprm[a * mjNGAIN];
  if (law->gear == 0 || law->gain == 0) {
    *error = name + " has gear " + std::to_string(law->gear) + " and gain " +
             std::to_string(law->gain) + ": both must be non-zero for its torque to be commanded";
    return false;
  }
  if (bias == mjBIAS_AFFINE) {
    for (int k = 0; k < 3; ++k) law->bias[k] = m->actuator_biasprm[a * mjNBIAS + k];
  }
  // MuJoCo clamps ctrl unless the model disables it; forcerange always applies when limited
  law->ctrl_limited = m->actuator_ctrllimited[a] && !(m->opt.disableflags & mjDSBL_CLAMPCTRL);
  law->ctrl_min = m->actuator_ctrlrange[2 * a];
  law->ctrl_max = m->actuator_ctrlrange[2 * a + 1];
  law->force_limited = m->actuator_forcelimited[a];
  law->force_min = m->actuator_forcerange[2 * a];
  law->force_max = m->actuator_forcerange[2 * a + 1];
  law->kind = Classify(*law, bias == mjBIAS_AFFINE);
  return true;
}

}  // namespace ohrp::model
