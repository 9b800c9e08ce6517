// The emulated HRP-1S's left elbow as the model has it, for the identification tests on
// hw_emulator (joints_emulator_test.cc, sensors_emulator_test.cc).
#pragma once

#include <mujoco/mujoco.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

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

}  // namespace ohrp::identify::testing
