// The emulated HRP-1S's left elbow, for the identification tests on hw_emulator
// (joints_emulator_test.cc, sensors_emulator_test.cc): its inertia as the model has it, and
// excite's chirp driven into it through the boards.
#pragma once

#include <mujoco/mujoco.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "controllers/excite.h"
#include "hw_driver/robot_io.h"
#include "identify/joints.h"
#include "robot_model/model.h"

namespace ohrp::identify::testing {

// the elbow's inertia about its axis in the half-sitting posture of `scene`, from the model (its
// armature included), the parent still; `*joint` its segment index
inline double ModelElbowInertia(const std::string& scene_path, int* joint) {
  std::string e;
  auto scene = model::Scene::Load(scene_path, &e);
  EXPECT_TRUE(scene) << e;
  model::RobotMap map;
  EXPECT_TRUE(model::MapRobot(scene->m(), &map, &e)) << e;
  EXPECT_TRUE(scene->Reset("halfsit", &e)) << e;
  mj_forward(scene->m(), scene->d());
  for (size_t j = 0; j < map.joints.size(); ++j)
    if (map.joints[j].name == "LARM_ELBOW") *joint = static_cast<int>(j);
  const int dof = map.joints[*joint].dof_adr, nv = scene->m()->nv;
  std::vector<double> full(static_cast<size_t>(nv) * nv);
  mj_fullM(scene->m(), full.data(), scene->d()->qM);
  return full[static_cast<size_t>(dof) * nv + dof];
}

// The board-cycle callback (the emulator fixture's Drive) that drives excite's chirp `x` into
// `joint` (the rest held), starting 1 s into the run from the commanded posture, and logs each
// new state into `log` as excite writes it: the reference, its rate over the interval since the
// last state seen, and the measured angle, rate and torque. `log` must outlive the drive.
inline std::function<void(const hw::IoState&, hw::IoCommand*)> ChirpInto(
    int joint, const controllers::ExciteOptions& x, JointLog* log) {
  struct Last {
    double q0 = 0, ref = 0;
    uint64_t time = 0;
  };
  return [joint, x, log, last = Last{}](const hw::IoState& s, hw::IoCommand* c) mutable {
    if (s.time_ns == last.time) return;  // no new state: the command stands
    last.time = s.time_ns;
    const double t = s.time_ns * 1e-9;
    if (log->t.empty()) last.q0 = last.ref = c->joint[joint].q_ref;
    const double ref = last.q0 + x.amplitude * controllers::ExciteSignalValue(
                                                   controllers::ExciteSignal::kChirp, x, {}, t - 1.0);
    c->joint[joint].q_ref = ref;
    c->joint[joint].dq_ref = log->t.empty() ? 0.0 : (ref - last.ref) / (t - log->t.back());
    last.ref = ref;
    log->t.push_back(t), log->ref.push_back(ref), log->q.push_back(s.q[joint]);
    log->dq.push_back(s.dq[joint]), log->tau.push_back(s.tau[joint]);
  };
}

}  // namespace ohrp::identify::testing
