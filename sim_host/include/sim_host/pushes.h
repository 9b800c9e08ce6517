// Pushes on the base: the one representation of a push (a window and a wrench), its `--push`
// text, and putting it on the base during the physics step (sim_host/step.h). In the library
// ohrp::sim_step, below sim_host: hw_emulator and the runner's scenario reader use it too.
#pragma once

#include <mujoco/mujoco.h>

#include <string>
#include <vector>

namespace ohrp::sim {

// An external push on the base: a wrench (world frame, at the base's centre of mass) applied
// from t0 to t1 of simulated time, e.g. to tilt the standing robot and release it. The wrench
// acts on every physics step that starts in [t0, t1) (to half a step), so a push lasts
// round((t1 - t0) / dt) steps and its impulse is force * that many steps * dt. Pushes whose
// windows overlap add.
struct Perturbation {
  double t0 = 0, t1 = 0;        // [s]
  double force[3] = {0, 0, 0};  // [N]
  double torque[3] = {0, 0, 0}; // [N m]
  bool active() const { return t1 > t0; }
};

// Parses one `--push` value "t0,t1,fx,fy,fz,tx,ty,tz" (8 finite numbers, t0 >= 0, t1 > t0).
// Returns false with `*error` saying what is wrong and how to write it.
bool ParsePerturbation(const std::string& spec, Perturbation* out, std::string* error);

// The `--push` value of `p`, "t0,t1,fx,fy,fz,tx,ty,tz" (%.17g: ParsePerturbation reads back the
// same numbers). The runner writes a scenario's pushes with it (a scenario's push is this window
// and force, given as a direction and an impulse or a force: runner/scenario.h's PushSpec).
std::string PerturbationText(const Perturbation& p);

// The total push wrench at simulated time `time` with physics step `dt`: the sum over the
// pushes whose window holds the step starting at `time` (see Perturbation). Writes 6 numbers
// (force then torque); no allocation.
void PushWrenchAt(const std::vector<Perturbation>& pushes, double time, double dt, double wrench[6]);

// True when push `p` acts on the physics step starting at `time` (step `dt`): the step starts
// in [t0, t1), to half a step (the rule of PushWrenchAt).
bool PushActiveAt(const Perturbation& p, double time, double dt);

// Puts the pushes' wrench for the step about to run on body `body`'s row of d->xfrc_applied.
// MuJoCo never clears xfrc_applied, so the row changes by the difference between the wrench
// wanted now and `pushed` (what the pushes put there before, updated here): other wrenches on
// the row stay. No allocation.
void ApplyPushes(const std::vector<Perturbation>& pushes, const mjModel* m, mjData* d, int body,
                 double pushed[6]);

}  // namespace ohrp::sim
