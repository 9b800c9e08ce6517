// The divergence diagnostic's likely cause, from the evidence gathered (divergence_diagnoser.h):
// the most specific explanation first, each stated with the numbers behind it and what to try.
#include <cmath>
#include <string>

#include "divergence_diagnoser.h"
#include "divergence_internal.h"

namespace ohrp::sim::divergence_internal {

void Diagnoser::Cause() {
  if (CauseInTheControl() || CauseInASole() || CauseInAGain() || CauseInAContact() ||
      CauseInTheSolver() || CauseNearTheLimit())
    return;
  x_.cause = "an explicit step too large for the fastest dynamics of the bodies listed (no "
             "single stiffness, gain, penetration or constraint explains it)";
  x_.suggestion = "halve --physics-dt until it stays finite, or the implicit integrator "
                  "(--integrator implicit); check the inertias of the light links";
}

// a non-finite or huge control
bool Diagnoser::CauseInTheControl() {
  if (w_.warning != mjWARN_BADCTRL) return false;
  const std::string act = w_.index >= 0 && w_.index < m_->nu ? Name(m_, mjOBJ_ACTUATOR, w_.index) : "?";
  x_.cause = "a non-finite or huge control on actuator " + act +
             ": the controller computed it (e.g. a singular Jacobian inverse, a division by a "
             "vanishing quantity); MuJoCo zeroes every control on NaN and silently clamps an "
             "infinite one to the actuator's range";
  x_.suggestion = "check the controller's numbers at this time (a damped least-squares inverse "
                  "near singular poses); sim_host's servo refuses such commands";
  return true;
}

// a soft-foot sole too stiff for the step, or one deep in the floor
bool Diagnoser::CauseInASole() {
  if (sole_number_ > kStableStepNumber) {
    x_.cause = "too large a step for the soft-foot sole " + sole_name_ + ": at its depth of " +
               Fmt("%.3g", sole_depth_ * 1e3) + " mm the spring-damper's explicit step number "
               "dt^2 K/m + 2 dt c k delta/m is " + Fmt("%.3g", sole_number_) +
               " (stable below 4) at dt = " + dt_text_;
    x_.suggestion = sole_depth_ > kDeepPenetration
                        ? "start the robot out of the floor (the sole began or ended " +
                              Fmt("%.3g", sole_depth_ * 1e3) + " mm deep: penetration), or a smaller "
                              "--physics-dt, or a lower soft-foot damping"
                        : "a smaller --physics-dt, or a lower soft-foot stiffness or damping "
                          "(the parameter check in contact/params.h gives the limits)";
    return true;
  }
  if (!ctx_.soft || sole_deepest_ <= kDeepPenetration) return false;
  const auto& p = ctx_.soft->params();
  x_.cause = "penetration: the soft-foot sole " + sole_deepest_name_ + " is " +
             Fmt("%.3g", sole_deepest_ * 1e3) + " mm deep; its spring (k = " +
             Fmt("%.3g", p.stiffness) + ") releases about k delta^(n+1)/(n+1) = " +
             Fmt("%.4g", p.stiffness * std::pow(sole_deepest_, p.exponent + 1) / (p.exponent + 1)) +
             " J as it pushes the robot out";
  x_.suggestion = "start the robot with its soles on the floor (a keyframe at the standing "
                  "height), or Hunt-Crossley damping (soft-foot damping > 0) which lets go as "
                  "the sole leaves";
  return true;
}

// a servo's or actuator's gain, or a joint's spring, too stiff for the step
bool Diagnoser::CauseInAGain() {
  if (gain_number_ <= kStableStepNumber) return false;
  x_.cause = (gain_is_spring_ ? "too large a step for the stiffness of " : "gain too high for the inertia: ") + gain_text_;
  x_.suggestion = gain_is_spring_
                      ? "a smaller --physics-dt (the limit scales with sqrt(I/k)), or a softer spring"
                      : "lower the gains, or a smaller --physics-dt (the limit scales with dt^2 "
                        "for kp, dt for kd), or the implicit integrator for kd of MuJoCo's own "
                        "actuators, or armature on the light link";
  return true;
}

// a MuJoCo contact too stiff for the step, or a deep one
bool Diagnoser::CauseInAContact() {
  if (contact_number_ > kStableStepNumber) {
    x_.cause = "too large a step for a contact's stiffness: " + contact_text_;
    x_.suggestion = "a positive solref time constant of at least two steps (MuJoCo scales it "
                    "with each contact's effective mass), or a smaller --physics-dt";
    return true;
  }
  if (deepest_ <= kDeepPenetration) return false;
  x_.cause = "penetration: " + deepest_pair_ + " is " + Fmt("%.3g", deepest_ * 1e3) +
             " mm deep; the contact pushes the bodies apart with the energy stored in the "
             "overlap";
  x_.suggestion = "start the bodies out of contact, or a softer contact (a larger solref time "
                  "constant), or a smaller --physics-dt";
  return true;
}

// an equality constraint or the solver's iteration limit
bool Diagnoser::CauseInTheSolver() {
  if (equality_.empty() && !solver_maxed_) return false;
  x_.cause = "the constraint solver" +
             (equality_.empty() ? std::string() : " (equality constraint " + equality_ + ")") +
             (solver_maxed_ ? " stopped at its iteration limit (" +
                                  std::to_string(d_->solver_iter) + " iterations)"
                            : std::string(" could not keep the constraints")) +
             eq_note_;
  x_.suggestion = !eq_note_.empty()
                      ? "a solref time constant of at least two steps for the equality (or "
                        "refsafe on), or a smaller --physics-dt"
                      : "more solver iterations, a smaller --physics-dt, or the implicit "
                        "integrator; check that the closed loop is consistent at the initial pose";
  return true;
}

// a sole or a gain within a factor of two of the explicit step's limit
bool Diagnoser::CauseNearTheLimit() {
  if (sole_number_ <= 0.5 * kStableStepNumber && gain_number_ <= 0.5 * kStableStepNumber)
    return false;
  x_.cause = "a stiff element close to the explicit step's limit: " +
             (gain_number_ >= sole_number_ ? gain_text_
                                           : "soft-foot sole " + sole_name_ + " step number " +
                                                 Fmt("%.3g", sole_number_));
  x_.suggestion = "a smaller --physics-dt";
  return true;
}

}  // namespace ohrp::sim::divergence_internal
