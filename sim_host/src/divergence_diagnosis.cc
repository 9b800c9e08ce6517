// The divergence watch's diagnostic: what went wrong, where, the likely cause and what to try
// (see divergence.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "divergence_diagnoser.h"
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

namespace divergence_internal {

bool Diagnoser::Detected() {
  switch (w_.kind) {
    case DivergenceKind::kNone:
      x_.what = "no divergence";
      x_.cause = "none";
      x_.suggestion = "nothing";
      return false;
    case DivergenceKind::kMujocoReset: {
      const char* what = w_.warning == mjWARN_BADQPOS   ? "a bad number in qpos"
                         : w_.warning == mjWARN_BADQVEL ? "a bad or huge number in qvel"
                         : w_.warning == mjWARN_BADQACC ? "a bad acceleration (qacc)"
                                                        : "a bad number in ctrl";
      x_.what = std::string("MuJoCo found ") + what + " and reset the state";
      break;
    }
    case DivergenceKind::kNonFinite:
      x_.what = w_.warning == mjWARN_BADCTRL ? "a control (ctrl) became non-finite"
                                             : "the state became non-finite";
      break;
    case DivergenceKind::kRunaway:
      x_.what = "a speed beyond " + Fmt("%g", w_.max_speed) + " m/s or rad/s";
      break;
    case DivergenceKind::kEnergy:
      x_.what = "energy blow-up: E - E(0) = " + Fmt("%.4g", w_.energy - w_.energy0) +
                " J while gravity, motors and pushes supplied at most " + Fmt("%.4g", w_.work) +
                " J (margin " + Fmt("%.4g", w_.margin) + " J)";
      break;
  }
  return true;
}

// the dofs, the flagged one first, then the largest |qvel| (|qacc| breaks ties and ranks when
// nothing moved yet), from the last finite state
std::vector<int> Diagnoser::DofsByMotion() const {
  std::vector<int> order(m_->nv);
  for (int i = 0; i < m_->nv; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double va = std::fabs(w_.qvel[a]), vb = std::fabs(w_.qvel[b]);
    if (va != vb) return va > vb;
    return std::fabs(w_.qacc[a]) > std::fabs(w_.qacc[b]);
  });
  const auto first = [&order](int dof) {
    order.erase(std::find(order.begin(), order.end(), dof));
    order.insert(order.begin(), dof);
  };
  const bool dof_index = (w_.kind == DivergenceKind::kNonFinite && w_.warning != mjWARN_BADCTRL) ||
                         w_.kind == DivergenceKind::kRunaway ||
                         (w_.kind == DivergenceKind::kMujocoReset &&
                          (w_.warning == mjWARN_BADQVEL || w_.warning == mjWARN_BADQACC));
  if (dof_index && w_.index >= 0 && w_.index < m_->nv) first(w_.index);
  if (w_.warning == mjWARN_BADCTRL && w_.index >= 0 && w_.index < m_->nu &&
      m_->actuator_trntype[w_.index] == mjTRN_JOINT)
    first(m_->jnt_dofadr[m_->actuator_trnid[2 * w_.index]]);
  return order;
}

void Diagnoser::InvolvedDofs() {
  const std::vector<int> order = DofsByMotion();
  for (int k = 0; k < std::min(3, m_->nv); ++k) {
    const int i = order[k];
    DofReport r;
    r.dof = i;
    const int j = m_->dof_jntid[i];
    r.joint = Name(m_, mjOBJ_JOINT, j);
    if (m_->jnt_type[j] == mjJNT_FREE || m_->jnt_type[j] == mjJNT_BALL) {
      static const char* kAxes[] = {"x", "y", "z", "rx", "ry", "rz"};
      const int axis = i - m_->jnt_dofadr[j] + (m_->jnt_type[j] == mjJNT_BALL ? 3 : 0);
      r.joint += std::string(" (") + (m_->jnt_type[j] == mjJNT_FREE ? "free " : "ball ") +
                 kAxes[axis] + ")";
    }
    r.body = Name(m_, mjOBJ_BODY, m_->dof_bodyid[i]);
    r.qvel = w_.qvel[i];
    r.qacc = w_.qacc[i];
    r.inertia = Inertia(m_, d_, i);
    x_.dofs.push_back(r);
    if (std::find(bodies_.begin(), bodies_.end(), m_->dof_bodyid[i]) == bodies_.end())
      bodies_.push_back(m_->dof_bodyid[i]);
  }
  for (int b : bodies_) x_.bodies.push_back(Name(m_, mjOBJ_BODY, b));
}

// b is the body of a listed dof or moves with it (a descendant)
bool Diagnoser::Involved(int b) const {
  for (int c : bodies_)
    for (int p = b; p > 0; p = m_->body_parentid[p])
      if (p == c) return true;
  return false;
}

// contacts touching the involved bodies (MuJoCo's), deepest first
void Diagnoser::Contacts() {
  for (int c = 0; c < d_->ncon; ++c) {
    const mjContact& con = d_->contact[c];
    const int b1 = m_->geom_bodyid[con.geom1], b2 = m_->geom_bodyid[con.geom2];
    if (!Involved(b1) && !Involved(b2) && d_->ncon > 8) continue;
    const std::string pair = Name(m_, mjOBJ_GEOM, con.geom1) + "/" + Name(m_, mjOBJ_GEOM, con.geom2);
    if (x_.contacts.size() < 6)
      x_.contacts.push_back(pair + " depth " + Fmt("%.3g", -con.dist * 1e3) + " mm");
    if (-con.dist > deepest_) {
      deepest_ = -con.dist;
      deepest_pair_ = pair;
    }
    // a contact stiffer than the step can integrate: a direct stiffness (solref < 0) on the
    // lighter body, or a time constant below two steps with MuJoCo's refsafe clamp off
    const double m1 = b1 > 0 ? m_->body_mass[b1] : 0, m2 = b2 > 0 ? m_->body_mass[b2] : 0;
    const double light = m1 > 0 && m2 > 0 ? std::min(m1, m2) : std::max(m1, m2);
    double number = 0;
    std::string what;
    if (con.solref[0] < 0 && light > 0) {
      number = dt_ * dt_ * (-con.solref[0]) / light;
      what = "the contact " + pair + " has a direct stiffness of " + Fmt("%.3g", -con.solref[0]) +
             " N/m (solref < 0) acting on " + Fmt("%.3g", light) + " kg: dt^2 k/m = " +
             Fmt("%.3g", number) + " (stable below 4)";
    } else if (con.solref[0] > 0 && (m_->opt.disableflags & mjDSBL_REFSAFE) &&
               con.solref[0] < 2 * dt_) {
      const double tc = con.solref[0];
      number = 4.0 * dt_ * dt_ / (tc * tc);  // (omega dt)^2 with omega ~ 2 / tc
      what = "the contact " + pair + " has a time constant of " + Fmt("%.3g", tc) +
             " s, below two steps, with refsafe off";
    }
    if (number > contact_number_) {
      contact_number_ = number;
      contact_text_ = what;
    }
  }
}

// the soft-foot soles: their contacts, and the explicit step number of each sole's
// spring-damper at its present depth
void Diagnoser::Soles() {
  if (!ctx_.soft) return;
  const auto& p = ctx_.soft->params();
  const auto& w = ctx_.soft->wrenches();
  for (size_t s = 0; s < w.size() && s < ctx_.soft->sole_geoms().size(); ++s) {
    const std::string name = Name(m_, mjOBJ_GEOM, ctx_.soft->sole_geoms()[s]);
    if (w[s].in_contact && x_.contacts.size() < 6)
      x_.contacts.push_back(name + " (soft-foot) depth " + Fmt("%.3g", w[s].depth * 1e3) +
                            " mm, " + Fmt("%.4g", w[s].normal_force) + " N");
    const double delta = std::max(0.0, w[s].depth);
    if (w[s].in_contact && delta > sole_deepest_) {
      sole_deepest_ = delta;
      sole_deepest_name_ = name;
    }
    if (!w[s].in_contact || ctx_.soft_mass_scale <= 0) continue;
    const double K = p.exponent * p.stiffness * std::pow(delta, p.exponent - 1.0);
    const double beta = p.damping * p.stiffness * std::pow(delta, p.exponent) / ctx_.soft_mass_scale;
    const double number = dt_ * dt_ * K / ctx_.soft_mass_scale + 2 * dt_ * beta;
    if (number > sole_number_) {
      sole_number_ = number;
      sole_depth_ = delta;
      sole_name_ = name;
    }
  }
}

void Diagnoser::ConsiderGain(int dof, double kp, double kd, const std::string& who) {
  const double inertia = Inertia(m_, d_, dof);
  if (inertia <= 0) return;
  // joint damping is integrated implicitly by MuJoCo's Euler; a servo's kd is not
  const double number = dt_ * dt_ * kp / inertia + 2 * dt_ * kd / inertia;
  if (number <= gain_number_) return;
  gain_number_ = number;
  gain_is_spring_ = who == "the joint spring";
  const double kp_max = 0.5 * kStableStepNumber * inertia / (dt_ * dt_);
  gain_text_ = who + " on joint " + Name(m_, mjOBJ_JOINT, m_->dof_jntid[dof]) + " (kp " +
               Fmt("%.3g", kp) + ", kd " + Fmt("%.3g", kd) + " on an inertia of " +
               Fmt("%.3g", inertia) + "): dt^2 kp/I + 2 dt kd/I = " + Fmt("%.3g", number) +
               " at dt = " + dt_text_ + " (the explicit step is stable below 4); kp <= " +
               Fmt("%.3g", kp_max) + " with kd <= " +
               Fmt("%.3g", 0.25 * kStableStepNumber * inertia / dt_) + " would be stable";
}

// the gains acting on the involved dofs: the servo's, MuJoCo's position/velocity actuators, and
// the joints' stiffness (integrated explicitly)
void Diagnoser::Gains() {
  for (const auto& g : ctx_.gains)
    if (g.dof >= 0 && g.dof < m_->nv && Involved(m_->dof_bodyid[g.dof]))
      ConsiderGain(g.dof, g.kp, g.kd, "the servo");
  for (int a = 0; a < m_->nu; ++a) {
    if (m_->actuator_trntype[a] != mjTRN_JOINT) continue;
    const int dof = m_->jnt_dofadr[m_->actuator_trnid[2 * a]];
    if (!Involved(m_->dof_bodyid[dof])) continue;
    const double* bias = m_->actuator_biasprm + mjNBIAS * a;
    const double kp = -bias[1], kd = -bias[2];
    if (m_->actuator_biastype[a] == mjBIAS_AFFINE && (kp > 0 || kd > 0))
      ConsiderGain(dof, std::max(0.0, kp), std::max(0.0, kd),
                   "actuator " + Name(m_, mjOBJ_ACTUATOR, a));
  }
  for (int j = 0; j < m_->njnt; ++j) {
    if (m_->jnt_stiffness[j] <= 0 || !Involved(m_->jnt_bodyid[j])) continue;
    if (m_->jnt_type[j] != mjJNT_HINGE && m_->jnt_type[j] != mjJNT_SLIDE) continue;
    ConsiderGain(m_->jnt_dofadr[j], m_->jnt_stiffness[j], 0, "the joint spring");
  }
}

// equality constraints touching the involved bodies, and the solver's state
void Diagnoser::Constraints() {
  for (int e = 0; e < m_->neq; ++e) {
    if (!m_->eq_active[e]) continue;
    if (Involved(m_->eq_obj1id[e]) || Involved(m_->eq_obj2id[e]) ||
        m_->eq_type[e] == mjEQ_JOINT || m_->eq_type[e] == mjEQ_TENDON) {
      equality_ = Name(m_, mjOBJ_EQUALITY, e);
      const double tc = m_->eq_solref[mjNREF * e];
      if ((m_->opt.disableflags & mjDSBL_REFSAFE) && tc > 0 && tc < 2 * dt_)
        eq_note_ = "; its time constant " + Fmt("%.3g", tc) +
                   " s is below two steps and MuJoCo's refsafe clamp is off";
      break;
    }
  }
  solver_maxed_ = d_->solver_iter >= m_->opt.iterations && d_->nefc > 0;
}

}  // namespace divergence_internal

Diagnosis DivergenceWatch::Diagnose(const mjModel* m, const mjData* d,
                                    const DiagnosisContext& ctx) const {
  Diagnosis x;
  x.kind = kind_;
  x.step = step_;
  x.time = time_;
  x.energy = energy_;
  x.energy_start = energy0_;
  x.input_work = work_;
  const Latched latched{kind_,    warning_, index_,  last_qvel_, last_qacc_,
                        limits_.max_speed, energy_, energy0_, work_, margin_};
  Diagnoser diagnose(m, d, ctx, latched, &x);
  if (!diagnose.Detected()) return x;
  diagnose.InvolvedDofs();
  diagnose.Contacts();
  diagnose.Soles();
  diagnose.Gains();
  diagnose.Constraints();
  diagnose.Cause();
  return x;
}

}  // namespace ohrp::sim
