// MJCF text from the VRML kinematic tree (see model_tree.h, robot_profile.h).
#pragma once

#include <string>

#include "vrml/model_tree.h"

namespace ohrp::vrml {

// Writes the scene as one MJCF document; names the robot's sole geoms in `model` on the way.
// Returns false with `*error` set when the robot's jointIds are not 0..n-1 (each once).
bool WriteMjcf(Model* model, std::string* mjcf, std::string* error);

}  // namespace ohrp::vrml
