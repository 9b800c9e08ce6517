// The run-time divergence watch: after every physics step, a cheap check (no allocation, no
// logging) that the simulation is still meaningful; on the first failure, a diagnostic that
// names the step, the simulated time, the joints and bodies involved, the contacts they touch,
// the likely cause and what to try.
//
// What counts as divergence (checked in this order, every step):
//   1. MuJoCo reset the state: the count of mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC or
//      mjWARN_BADCTRL grew. MuJoCo then zeroes or resets qpos/qvel/ctrl and goes on, so the
//      state after such a step is finite but garbage (qvel beyond 1e10 triggers it too).
//   2. a non-finite qpos, qvel, qacc or ctrl (MuJoCo clamps an infinite control of a limited
//      actuator without a warning), or a speed beyond WatchLimits::max_speed (a runaway that
//      will be non-finite a few steps later).
//   3. energy blow-up. E = kinetic + gravity + joint/tendon spring energy (MuJoCo's definition
//      of mj_energyPos, computed by the watch itself whatever the scene's `energy` flag: MuJoCo
//      2.2 leaves it 0 when the flag is off, which made any fall look like energy from nowhere;
//      and qvel' M qvel) of the state after the step, with the kinematics and mass
//      matrix mj_step left in mjData (those of the step's start: E is off by about
//      M |g| |v| dt, 0.1 J for 1 kg at 10 m/s at 1 ms). What can raise E is bounded by the
//      work of the sources:
//          W(t) = sum over steps of dt * ( sum_i max(0, qfrc_actuator_i qvel_i)
//                                        + sum_i max(0, qfrc_applied_i qvel_i)
//                                        + sum over active bodies of max(0, xfrc_applied . v) )
//      (only the positive part: a motor or a push can add at most its positive work; a PD's
//      stored "spring" energy released again is counted as input, which keeps W generous).
//      Contacts (MuJoCo's and the soft-foot soles, declared passive with SetPassiveBodies),
//      joint damping and the constraint solver cannot add energy. The run diverged when
//          E(t) - E(0) - W(t) > margin,  margin = M_total * max(|g|, 1 m/s^2) * energy_height
//      with energy_height = 1 m by default: the robot gained, from nothing that can supply it,
//      more than the energy of a fall from one metre. Discretisation and soft-constraint errors
//      of a stable run stay orders of magnitude below that; an explicit step beyond its stable
//      range grows E geometrically and crosses it within a few periods.
//
// Usage (sim_host's RunHost):
//   DivergenceWatch watch(m);                  // after the model is final (overrides, feet)
//   watch.SetPassiveBodies(sole bodies);       // the soft-foot writes xfrc_applied
//   watch.Start(m, d);                         // after the reset: E(0), warning baselines
//   ... mj_step(m, d); if (watch.Check(m, d, step)) { Diagnosis x = watch.Diagnose(m, d, ctx); }
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <string>
#include <vector>

#include "contact/soft_contact.h"

namespace ohrp::sim {

enum class DivergenceKind {
  kNone,
  kMujocoReset,  // MuJoCo found a bad number and reset the state (warning counted)
  kNonFinite,    // a non-finite qpos / qvel / qacc / ctrl
  kRunaway,      // a speed beyond WatchLimits::max_speed
  kEnergy,       // energy above what gravity, motors and pushes could have supplied
};
const char* DivergenceKindName(DivergenceKind kind);

struct WatchLimits {
  double energy_height = 1.0;  // [m] margin of the energy test, as a fall height of the model
  double max_speed = 1e4;      // [m/s or rad/s] any |qvel| above this is a runaway
};

// What the host knows and the model does not show, for the cause analysis (all optional).
struct DiagnosisContext {
  // the soft-foot contact, when it acts (its parameters, sole depths and forces are read)
  const contact::SoftFootContact* soft = nullptr;
  double soft_mass_scale = 0;  // [kg] the mass SetUpFeet validated it for (robot mass / 2)
  // PD gains acting on dofs through d->ctrl (sim_host's servo): dof address, kp, kd
  struct Gain {
    int dof = -1;
    double kp = 0;  // [N m/rad or N/m]
    double kd = 0;  // [N m s/rad or N s/m]
  };
  std::vector<Gain> gains;
};

// A dof that moved most at the failure.
struct DofReport {
  int dof = -1;
  std::string joint;  // MuJoCo joint name ("" when unnamed: the joint id is given)
  std::string body;   // the body the dof moves
  double qvel = 0;    // [rad/s or m/s] at the last step the state was finite
  double qacc = 0;    // [rad/s^2 or m/s^2]
  double inertia = 0; // diagonal of the mass matrix [kg m^2 or kg], armature included
};

struct Diagnosis {
  DivergenceKind kind = DivergenceKind::kNone;
  uint64_t step = 0;  // physics step count (1 = after the first mj_step)
  double time = 0;    // [s] simulated time of the last finite state
  std::string what;   // what was detected, one sentence
  std::vector<DofReport> dofs;       // the dofs with the largest |qvel| (then |qacc|), at most 3
  std::vector<std::string> bodies;   // their bodies, each once
  std::vector<std::string> contacts; // contacts touching those bodies: "A/B depth 3.1 mm"
  std::string cause;       // likely cause, one sentence with the numbers behind it
  std::string suggestion;  // what to try
  double energy = 0, energy_start = 0, input_work = 0;  // [J] at detection
  // one paragraph: what, where (step, time, bodies), cause, suggestion
  std::string Text() const;
};

class DivergenceWatch {
 public:
  // `m` must be the model as it will be stepped (time step, integrator, contact set up).
  // Allocates everything the per-step check needs.
  explicit DivergenceWatch(const mjModel* m, const WatchLimits& limits = {});

  // Bodies whose xfrc_applied is a passive contact force (the soft-foot soles): its work is
  // not counted as input.
  void SetPassiveBodies(const std::vector<int>& bodies);

  // Baselines from the current state: the warning counts, E(0), W = 0. Runs mj_forward.
  void Start(const mjModel* m, mjData* d);

  // After each mj_step: true when the run has diverged (the first detection is latched with
  // the last finite state; later calls return true and change nothing). No allocation, no
  // output. Writes d->energy (the potential energy in d->energy[0], the kinetic in [1]).
  bool Check(const mjModel* m, mjData* d, uint64_t step);

  // The diagnostic of the latched detection (allocates; call once, after Check returned true).
  Diagnosis Diagnose(const mjModel* m, const mjData* d, const DiagnosisContext& context = {}) const;

  bool diverged() const { return kind_ != DivergenceKind::kNone; }
  DivergenceKind kind() const { return kind_; }
  double energy() const { return energy_; }              // [J] E at the last check
  double energy_start() const { return energy0_; }       // [J] E(0)
  double input_work() const { return work_; }            // [J] W so far
  double margin() const { return margin_; }              // [J]
  double max_excess() const { return max_excess_; }      // [J] largest E - E(0) - W so far

 private:
  void Latch(DivergenceKind kind, uint64_t step, int index);
  double Energy(const mjModel* m, mjData* d);

  WatchLimits limits_;
  double margin_ = 0;
  std::vector<char> passive_;          // per body
  int baseline_[mjNWARNING] = {};
  double energy0_ = 0, energy_ = 0, work_ = 0, max_excess_ = 0;
  // the last finite state (copied every step: nq + 2 nv doubles, no allocation)
  std::vector<double> last_qpos_, last_qvel_, last_qacc_;
  double last_time_ = 0;
  // the latched detection
  DivergenceKind kind_ = DivergenceKind::kNone;
  uint64_t step_ = 0;
  double time_ = 0;
  int index_ = -1;  // the offending dof / qpos index / warning info, by kind
  int warning_ = -1;
};

}  // namespace ohrp::sim
