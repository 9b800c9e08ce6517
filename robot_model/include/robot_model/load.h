// The one way every program loads a robot's model: sim_host, the controllers, hw_driver and
// hw_emulator, the tools. One path, the same model everywhere (the model hash agrees).
#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

namespace ohrp::model {

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;

// Loads `path` into a MuJoCo model:
//   - a robot profile (.yaml, .yml: robot_model/profile.h): its model with the profile applied,
//     in memory;
//   - an OpenHRP VRML file (.wrl): converted in memory (vrml/vrml.h);
//   - anything else: MJCF or URDF, given to MuJoCo as it is.
// Returns the model (the caller owns it: mj_deleteModel) or null with `*error` naming the file.
mjModel* LoadMujocoModel(const std::string& path, std::string* error);

// MJCF text loaded through MuJoCo's virtual file system under `vfs_name` (a path: its folder is
// where relative asset paths resolve; nothing is written there). `what` names it in messages.
mjModel* LoadMjcfText(const std::string& text, const std::string& vfs_name,
                      const std::string& what, std::string* error);

}  // namespace ohrp::model
