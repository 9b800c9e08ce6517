// Internal to sim_host's divergence watch: the diagnostic's stages over one latched detection
// (divergence_diagnosis.cc: what, where and the evidence; divergence_cause.cc: the likely cause).
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

#include "divergence_internal.h"
#include "sim_host/divergence.h"

namespace ohrp::sim::divergence_internal {

// what the watch latched at the detection (DivergenceWatch's state, read by the diagnostic)
struct Latched {
  DivergenceKind kind;
  int warning, index;
  const std::vector<double>& qvel;
  const std::vector<double>& qacc;
  double max_speed, energy, energy0, work, margin;
};

// The diagnostic's stages over one latched detection: what was detected, the dofs and bodies
// involved, the evidence (MuJoCo's contacts, the soft-foot soles, the gains and springs, the
// constraints: each as an explicit step number against the stable 4), then the likely cause,
// most specific first.
class Diagnoser {
 public:
  Diagnoser(const mjModel* m, const mjData* d, const DiagnosisContext& ctx, const Latched& w,
            Diagnosis* x)
      : m_(m), d_(d), ctx_(ctx), w_(w), x_(*x), dt_(m->opt.timestep),
        dt_text_(Fmt("%g", m->opt.timestep) + " s") {}

  bool Detected();  // false: nothing was
  void InvolvedDofs();
  void Contacts();
  void Soles();
  void Gains();
  void Constraints();
  void Cause();

 private:
  std::vector<int> DofsByMotion() const;
  bool Involved(int b) const;
  void ConsiderGain(int dof, double kp, double kd, const std::string& who);
  // Cause's candidates, most specific first: each true when it explains the divergence (and
  // then has written the cause and the suggestion)
  bool CauseInTheControl();
  bool CauseInASole();
  bool CauseInAGain();
  bool CauseInAContact();
  bool CauseInTheSolver();
  bool CauseNearTheLimit();

  const mjModel* m_;
  const mjData* d_;
  const DiagnosisContext& ctx_;
  const Latched& w_;
  Diagnosis& x_;
  const double dt_;
  const std::string dt_text_;
  std::vector<int> bodies_;  // the involved dofs' bodies
  // MuJoCo's contacts: the deepest, and the stiffest for the step
  double deepest_ = 0, contact_number_ = 0;
  std::string deepest_pair_, contact_text_;
  // the soft-foot soles: the stiffest for the step, and the deepest
  double sole_depth_ = 0, sole_number_ = 0, sole_deepest_ = 0;
  std::string sole_name_, sole_deepest_name_;
  // the gains and springs on the involved dofs
  double gain_number_ = 0;
  bool gain_is_spring_ = false;
  std::string gain_text_;
  // the constraints
  std::string equality_, eq_note_;
  bool solver_maxed_ = false;
};

}  // namespace ohrp::sim::divergence_internal
