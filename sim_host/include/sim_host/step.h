// sim_host's physics step, the one every caller runs (sim_host's loop, the in-process robot,
// the benchmarks, the accuracy tool, the tests), so that each times and tests the real step:
//   pushes -> servo -> soft contact (implicit force, contact/soft_contact.h) -> mj_step
//   -> commit of the contact's friction state -> divergence watch.
// With the Euler integrator, joint damping is folded into the armature for the step
// (sim_host/damping_fold.h): MuJoCo's implicit damping with one factorisation of M, not two.
// With the soft soles and the Euler or implicit integrator, the step is MuJoCo's mj_step1, the
// contact, mj_step2: the contact reads the kinematics and the factorised mass matrix that
// mj_step1 computed for the step instead of computing them once more (same forces, same state).
// Every part but the model is optional (null / empty). Per step: no allocation, no throw, no
// log (the watch's diagnosis, which allocates, is the caller's, after Step() returned false).
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <vector>

#include "contact/soft_contact.h"
#include "robot_model/servo.h"
#include "sim_host/damping_fold.h"
#include "sim_host/divergence.h"
#include "sim_host/pushes.h"

namespace ohrp::sim {

class PhysicsStep {
 public:
  // The parts, owned by the caller and alive while this is used.
  struct Parts {
    model::Servo* servo = nullptr;                    // applies its law into d->ctrl / qfrc
    contact::SoftFootContact* soft = nullptr;         // the soft soles
    const std::vector<Perturbation>* pushes = nullptr;  // pushes on `push_body`
    int push_body = -1;
    DivergenceWatch* watch = nullptr;                 // checked after each step
  };
  PhysicsStep(mjModel* m, mjData* d, const Parts& parts);

  // One physics step. False when the watch latched a divergence (the state is then not
  // advanced any more by the caller's choice; the watch says why). `sensors` false: MuJoCo's
  // sensors are not computed on this step (mjDSBL_SENSOR for the step; sensordata keeps its
  // last values), for the steps of a control cycle before its last, whose sensordata nobody
  // reads: the force/torque and accelerometer sensors' pass (mj_rnePostConstraint) is about
  // 8 % of HRP-1S's step. The state the step reaches does not depend on it.
  bool Step(bool sensors = true);

  // push i acted on the last step / changed (started or ended) with the last step
  bool push_on(size_t i) const { return push_on_[i] != 0; }
  bool push_changed(size_t i) const { return push_changed_[i] != 0; }
  uint64_t steps() const { return steps_; }

 private:
  mjModel* m_;
  mjData* d_;
  Parts parts_;
  double pushed_[6] = {0, 0, 0, 0, 0, 0};  // the push wrench now in xfrc_applied
  std::vector<char> push_on_, push_changed_;
  DampingFold fold_;
  uint64_t steps_ = 0;
};

}  // namespace ohrp::sim
