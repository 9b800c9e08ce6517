// A URDF robot under a robot profile: the URDF as MJCF text, and what a URDF lacks made in the
// tree before anything is derived (the profile keys base and actuators; docs/robots.md).
#pragma once

#include <mujoco/mujoco.h>

#include <string>

#include "profile/mjcf_tree.h"
#include "robot_model/profile.h"

namespace ohrp::model::profile {

// The URDF at `path` compiled by MuJoCo (its root link kept a body: fusestatic="false") and
// saved as MJCF text. False with `*error` set when MuJoCo refuses it.
bool UrdfText(const std::string& path, std::string* text, std::string* error);

// `base: free` (a free joint on the first body under <worldbody>) and `actuators:` (one per
// joint) added to the tree `root` (the <mujoco> element) of model `m`. False with `*error`
// listing every problem.
bool PrepareRobot(const RobotProfile& p, const mjModel* m, mjcf::Tree* root, std::string* error);

}  // namespace ohrp::model::profile
