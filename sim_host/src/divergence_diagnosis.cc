// The divergence watch's diagnostic: what went wrong, where, the likely cause and what to try
// (see divergence.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "divergence_internal.h"
#include "sim_host/divergence.h"

namespace ohrp::sim {

using namespace divergence_internal;  // NOLINT: the watch's own helpers

//---------------- the diagnostic ----------------

std::string Diagnosis::Text() const {
  std::ostringstream s;
  s << what << " at step " << step << " (t = " << Fmt("%.4f", time) << " s)";
  if (!dofs.empty()) {
    s << "; moving most: ";
    for (size_t i = 0; i < dofs.size(); ++i) {
      const auto& x = dofs[i];
      s << (i ? ", " : "") << "joint " << x.joint << " of body " << x.body << " (qvel "
        << Fmt("%.3g", x.qvel) << ", qacc " << Fmt("%.3g", x.qacc) << ", inertia "
        << Fmt("%.3g", x.inertia) << ")";
    }
  }
  if (!contacts.empty()) {
    s << "; contacts: ";
    for (size_t i = 0; i < contacts.size(); ++i) s << (i ? ", " : "") << contacts[i];
  }
  s << ". Likely cause: " << cause << ". Try: " << suggestion;
  return s.str();
}

Diagnosis DivergenceWatch::Diagnose(const mjModel* m, const mjData* d,
                                    const DiagnosisContext& ctx) const {
  Diagnosis x;
  x.kind = kind_;
  x.step = step_;
  x.time = time_;
  x.energy = energy_;
  x.energy_start = energy0_;
  x.input_work = work_;
  const double dt = m->opt.timestep;
  const std::string dt_text = Fmt("%g", dt) + " s";

  // what was detected
  switch (kind_) {
    case DivergenceKind::kNone:
      x.what = "no divergence";
      x.cause = "none";
      x.suggestion = "nothing";
      return x;
    case DivergenceKind::kMujocoReset: {
      const char* what = warning_ == mjWARN_BADQPOS   ? "a bad number in qpos"
                         : warning_ == mjWARN_BADQVEL ? "a bad or huge number in qvel"
                         : warning_ == mjWARN_BADQACC ? "a bad acceleration (qacc)"
                                                      : "a bad number in ctrl";
      x.what = std::string("MuJoCo found ") + what + " and reset the state";
      break;
    }
    case DivergenceKind::kNonFinite:
      x.what = warning_ == mjWARN_BADCTRL ? "a control (ctrl) became non-finite"
                                          : "the state became non-finite";
      break;
    case DivergenceKind::kRunaway:
      x.what = "a speed beyond " + Fmt("%g", limits_.max_speed) + " m/s or rad/s";
      break;
    case DivergenceKind::kEnergy:
      x.what = "energy blow-up: E - E(0) = " + Fmt("%.4g", energy_ - energy0_) +
               " J while gravity, motors and pushes supplied at most " + Fmt("%.4g", work_) +
               " J (margin " + Fmt("%.4g", margin_) + " J)";
      break;
  }

  // the dofs involved: the flagged one first, then the largest |qvel| (|qacc| breaks ties and
  // ranks when nothing moved yet), from the last finite state
  std::vector<int> order(m->nv);
  for (int i = 0; i < m->nv; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double va = std::fabs(last_qvel_[a]), vb = std::fabs(last_qvel_[b]);
    if (va != vb) return va > vb;
    return std::fabs(last_qacc_[a]) > std::fabs(last_qacc_[b]);
  });
  const bool dof_index = (kind_ == DivergenceKind::kNonFinite && warning_ != mjWARN_BADCTRL) ||
                         kind_ == DivergenceKind::kRunaway ||
                         (kind_ == DivergenceKind::kMujocoReset &&
                          (warning_ == mjWARN_BADQVEL || warning_ == mjWARN_BADQACC));
  if (dof_index && index_ >= 0 && index_ < m->nv) {
    order.erase(std::find(order.begin(), order.end(), index_));
    order.insert(order.begin(), index_);
  }
  if (warning_ == mjWARN_BADCTRL && index_ >= 0 &&
      index_ < m->nu && m->actuator_trntype[index_] == mjTRN_JOINT) {
    const int dof = m->jnt_dofadr[m->actuator_trnid[2 * index_]];
    order.erase(std::find(order.begin(), order.end(), dof));
    order.insert(order.begin(), dof);
  }
  std::vector<int> bodies;
  for (int k = 0; k < std::min(3, m->nv); ++k) {
    const int i = order[k];
    DofReport r;
    r.dof = i;
    const int j = m->dof_jntid[i];
    r.joint = Name(m, mjOBJ_JOINT, j);
    if (m->jnt_type[j] == mjJNT_FREE || m->jnt_type[j] == mjJNT_BALL) {
      static const char* kAxes[] = {"x", "y", "z", "rx", "ry", "rz"};
      const int k = i - m->jnt_dofadr[j] + (m->jnt_type[j] == mjJNT_BALL ? 3 : 0);
      r.joint += std::string(" (") + (m->jnt_type[j] == mjJNT_FREE ? "free " : "ball ") + kAxes[k] + ")";
    }
    r.body = Name(m, mjOBJ_BODY, m->dof_bodyid[i]);
    r.qvel = last_qvel_[i];
    r.qacc = last_qacc_[i];
    r.inertia = Inertia(m, d, i);
    x.dofs.push_back(r);
    if (std::find(bodies.begin(), bodies.end(), m->dof_bodyid[i]) == bodies.end())
      bodies.push_back(m->dof_bodyid[i]);
  }
  auto involved = [&](int b) {
    for (int c : bodies) {
      // b is the body of a listed dof or moves with it (a descendant)
      for (int p = b; p > 0; p = m->body_parentid[p])
        if (p == c) return true;
    }
    return false;
  };
  for (int b : bodies) x.bodies.push_back(Name(m, mjOBJ_BODY, b));

  // contacts touching those bodies (MuJoCo's), deepest first
  double deepest = 0, contact_number = 0;
  std::string deepest_pair, contact_text;
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& con = d->contact[c];
    const int b1 = m->geom_bodyid[con.geom1], b2 = m->geom_bodyid[con.geom2];
    if (!involved(b1) && !involved(b2) && d->ncon > 8) continue;
    const std::string pair = Name(m, mjOBJ_GEOM, con.geom1) + "/" + Name(m, mjOBJ_GEOM, con.geom2);
    if (x.contacts.size() < 6)
      x.contacts.push_back(pair + " depth " + Fmt("%.3g", -con.dist * 1e3) + " mm");
    if (-con.dist > deepest) {
      deepest = -con.dist;
      deepest_pair = pair;
    }
    // a contact stiffer than the step can integrate: a direct stiffness (solref < 0) on the
    // lighter body, or a time constant below two steps with MuJoCo's refsafe clamp off
    const double m1 = b1 > 0 ? m->body_mass[b1] : 0, m2 = b2 > 0 ? m->body_mass[b2] : 0;
    const double light = m1 > 0 && m2 > 0 ? std::min(m1, m2) : std::max(m1, m2);
    double number = 0;
    std::string what;
    if (con.solref[0] < 0 && light > 0) {
      number = dt * dt * (-con.solref[0]) / light;
      what = "the contact " + pair + " has a direct stiffness of " + Fmt("%.3g", -con.solref[0]) +
             " N/m (solref < 0) acting on " + Fmt("%.3g", light) + " kg: dt^2 k/m = " +
             Fmt("%.3g", number) + " (stable below 4)";
    } else if (con.solref[0] > 0 && (m->opt.disableflags & mjDSBL_REFSAFE) &&
               con.solref[0] < 2 * dt) {
      const double tc = con.solref[0];
      number = 4.0 * dt * dt / (tc * tc);  // (omega dt)^2 with omega ~ 2 / tc
      what = "the contact " + pair + " has a time constant of " + Fmt("%.3g", tc) +
             " s, below two steps, with refsafe off";
    }
    if (number > contact_number) {
      contact_number = number;
      contact_text = what;
    }
  }
  // the soft-foot soles
  double sole_depth = 0, sole_number = 0, sole_deepest = 0;
  std::string sole_name, sole_deepest_name;
  if (ctx.soft) {
    const auto& p = ctx.soft->params();
    const auto& w = ctx.soft->wrenches();
    for (size_t s = 0; s < w.size() && s < ctx.soft->sole_geoms().size(); ++s) {
      const std::string name = Name(m, mjOBJ_GEOM, ctx.soft->sole_geoms()[s]);
      if (w[s].in_contact && x.contacts.size() < 6)
        x.contacts.push_back(name + " (soft-foot) depth " + Fmt("%.3g", w[s].depth * 1e3) +
                             " mm, " + Fmt("%.4g", w[s].normal_force) + " N");
      const double delta = std::max(0.0, w[s].depth);
      if (w[s].in_contact && delta > sole_deepest) {
        sole_deepest = delta;
        sole_deepest_name = name;
      }
      if (!w[s].in_contact || ctx.soft_mass_scale <= 0) continue;
      // the explicit step number of the sole's spring-damper at its present depth
      const double K = p.exponent * p.stiffness * std::pow(delta, p.exponent - 1.0);
      const double beta = p.damping * p.stiffness * std::pow(delta, p.exponent) / ctx.soft_mass_scale;
      const double number = dt * dt * K / ctx.soft_mass_scale + 2 * dt * beta;
      if (number > sole_number) {
        sole_number = number;
        sole_depth = delta;
        sole_name = name;
      }
    }
  }

  // the gains acting on the involved dofs: the servo's and MuJoCo's position/velocity actuators
  double gain_number = 0;
  bool gain_is_spring = false;
  std::string gain_text;
  auto consider_gain = [&](int dof, double kp, double kd, const std::string& who) {
    const double inertia = Inertia(m, d, dof);
    if (inertia <= 0) return;
    // joint damping is integrated implicitly by MuJoCo's Euler; a servo's kd is not
    const double number = dt * dt * kp / inertia + 2 * dt * kd / inertia;
    if (number > gain_number) {
      gain_number = number;
      gain_is_spring = who == "the joint spring";
      const double kp_max = 0.5 * kStableStepNumber * inertia / (dt * dt);
      gain_text = who + " on joint " + Name(m, mjOBJ_JOINT, m->dof_jntid[dof]) + " (kp " +
                  Fmt("%.3g", kp) + ", kd " + Fmt("%.3g", kd) + " on an inertia of " +
                  Fmt("%.3g", inertia) + "): dt^2 kp/I + 2 dt kd/I = " + Fmt("%.3g", number) +
                  " at dt = " + dt_text + " (the explicit step is stable below 4); kp <= " +
                  Fmt("%.3g", kp_max) + " with kd <= " +
                  Fmt("%.3g", 0.25 * kStableStepNumber * inertia / dt) + " would be stable";
    }
  };
  for (const auto& g : ctx.gains)
    if (g.dof >= 0 && g.dof < m->nv && involved(m->dof_bodyid[g.dof]))
      consider_gain(g.dof, g.kp, g.kd, "the servo");
  for (int a = 0; a < m->nu; ++a) {
    if (m->actuator_trntype[a] != mjTRN_JOINT) continue;
    const int dof = m->jnt_dofadr[m->actuator_trnid[2 * a]];
    if (!involved(m->dof_bodyid[dof])) continue;
    const double* bias = m->actuator_biasprm + mjNBIAS * a;
    const double kp = -bias[1], kd = -bias[2];
    if (m->actuator_biastype[a] == mjBIAS_AFFINE && (kp > 0 || kd > 0))
      consider_gain(dof, std::max(0.0, kp), std::max(0.0, kd),
                    "actuator " + Name(m, mjOBJ_ACTUATOR, a));
  }
  // joint stiffness of the involved dofs (integrated explicitly)
  for (int j = 0; j < m->njnt; ++j) {
    if (m->jnt_stiffness[j] <= 0 || !involved(m->jnt_bodyid[j])) continue;
    if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) continue;
    consider_gain(m->jnt_dofadr[j], m->jnt_stiffness[j], 0, "the joint spring");
  }

  // equality constraints touching the involved bodies, and the solver's state
  std::string equality, eq_note;
  for (int e = 0; e < m->neq; ++e) {
    if (!m->eq_active[e]) continue;
    if (involved(m->eq_obj1id[e]) || involved(m->eq_obj2id[e]) ||
        m->eq_type[e] == mjEQ_JOINT || m->eq_type[e] == mjEQ_TENDON) {
      equality = Name(m, mjOBJ_EQUALITY, e);
      const double tc = m->eq_solref[mjNREF * e];
      if ((m->opt.disableflags & mjDSBL_REFSAFE) && tc > 0 && tc < 2 * dt)
        eq_note = "; its time constant " + Fmt("%.3g", tc) +
                  " s is below two steps and MuJoCo's refsafe clamp is off";
      break;
    }
  }
  const bool solver_maxed = d->solver_iter >= m->opt.iterations && d->nefc > 0;

  // the likely cause, most specific first
  if (warning_ == mjWARN_BADCTRL) {
    const std::string act = index_ >= 0 && index_ < m->nu ? Name(m, mjOBJ_ACTUATOR, index_) : "?";
    x.cause = "a non-finite or huge control on actuator " + act +
              ": the controller computed it (e.g. a singular Jacobian inverse, a division by a "
              "vanishing quantity); MuJoCo zeroes every control on NaN and silently clamps an "
              "infinite one to the actuator's range";
    x.suggestion = "check the controller's numbers at this time (a damped least-squares inverse "
                   "near singular poses); sim_host's servo refuses such commands";
  } else if (sole_number > kStableStepNumber) {
    x.cause = "too large a step for the soft-foot sole " + sole_name + ": at its depth of " +
              Fmt("%.3g", sole_depth * 1e3) + " mm the spring-damper's explicit step number "
              "dt^2 K/m + 2 dt c k delta/m is " + Fmt("%.3g", sole_number) +
              " (stable below 4) at dt = " + dt_text;
    x.suggestion = sole_depth > kDeepPenetration
                       ? "start the robot out of the floor (the sole began or ended " +
                             Fmt("%.3g", sole_depth * 1e3) + " mm deep: penetration), or a smaller "
                             "--physics-dt, or a lower soft-foot damping"
                       : "a smaller --physics-dt, or a lower soft-foot stiffness or damping "
                         "(the parameter check in contact/params.h gives the limits)";
  } else if (ctx.soft && sole_deepest > kDeepPenetration) {
    const auto& p = ctx.soft->params();
    x.cause = "penetration: the soft-foot sole " + sole_deepest_name + " is " +
              Fmt("%.3g", sole_deepest * 1e3) + " mm deep; its spring (k = " +
              Fmt("%.3g", p.stiffness) + ") releases about k delta^(n+1)/(n+1) = " +
              Fmt("%.4g", p.stiffness * std::pow(sole_deepest, p.exponent + 1) / (p.exponent + 1)) +
              " J as it pushes the robot out";
    x.suggestion = "start the robot with its soles on the floor (a keyframe at the standing "
                   "height), or Hunt-Crossley damping (soft-foot damping > 0) which lets go as "
                   "the sole leaves";
  } else if (gain_number > kStableStepNumber) {
    x.cause = (gain_is_spring ? "too large a step for the stiffness of " : "gain too high for the inertia: ") + gain_text;
    x.suggestion = gain_is_spring
                       ? "a smaller --physics-dt (the limit scales with sqrt(I/k)), or a softer spring"
                       : "lower the gains, or a smaller --physics-dt (the limit scales with dt^2 "
                         "for kp, dt for kd), or the implicit integrator for kd of MuJoCo's own "
                         "actuators, or armature on the light link";
  } else if (contact_number > kStableStepNumber) {
    x.cause = "too large a step for a contact's stiffness: " + contact_text;
    x.suggestion = "a positive solref time constant of at least two steps (MuJoCo scales it "
                   "with each contact's effective mass), or a smaller --physics-dt";
  } else if (deepest > kDeepPenetration) {
    x.cause = "penetration: " + deepest_pair + " is " + Fmt("%.3g", deepest * 1e3) +
              " mm deep; the contact pushes the bodies apart with the energy stored in the "
              "overlap";
    x.suggestion = "start the bodies out of contact, or a softer contact (a larger solref time "
                   "constant), or a smaller --physics-dt";
  } else if (!equality.empty() || solver_maxed) {
    x.cause = "the constraint solver" +
              (equality.empty() ? std::string() : " (equality constraint " + equality + ")") +
              (solver_maxed ? " stopped at its iteration limit (" +
                                  std::to_string(d->solver_iter) + " iterations)"
                            : std::string(" could not keep the constraints")) +
              eq_note;
    x.suggestion = !eq_note.empty()
                       ? "a solref time constant of at least two steps for the equality (or "
                         "refsafe on), or a smaller --physics-dt"
                       : "more solver iterations, a smaller --physics-dt, or the implicit "
                         "integrator; check that the closed loop is consistent at the initial pose";
  } else if (sole_number > 0.5 * kStableStepNumber || gain_number > 0.5 * kStableStepNumber) {
    x.cause = "a stiff element close to the explicit step's limit: " +
              (gain_number >= sole_number ? gain_text
                                          : "soft-foot sole " + sole_name + " step number " +
                                                Fmt("%.3g", sole_number));
    x.suggestion = "a smaller --physics-dt";
  } else {
    x.cause = "an explicit step too large for the fastest dynamics of the bodies listed (no "
              "single stiffness, gain, penetration or constraint explains it)";
    x.suggestion = "halve --physics-dt until it stays finite, or the implicit integrator "
                   "(--integrator implicit); check the inertias of the light links";
  }
  return x;
}

}  // namespace ohrp::sim
