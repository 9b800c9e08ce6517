// Forward kinematics of the VRML tree at set-up: the soles (the lowest Box of a foot link and
// the links below it) and the root height that puts them on z = 0 for given joint angles.
#pragma once

#include <map>
#include <string>

#include "vrml/model_tree.h"

namespace ohrp::vrml {

// the body named `name` in the tree below `b` (b included), or null
Body* FindBody(Body* b, const std::string& name);

// the lowest Box of `b` and its descendants at zero joint angles, `pose` being b's frame;
// `*lowest` is lowered to its lowest point's z [m]; null when there is no Box
Geom* LowestBox(Body* b, const Pose& pose, double* lowest);

// the lowest point of the named geoms (the soles) below `root`, with the root's frame at the
// origin turned by its own orientation, for joint angles `q` by joint name (others 0) [m]
double LowestNamedPoint(const Body& root, const std::map<std::string, double>& q);

// calls f(body) for `b` and every body below it, depth first (the order of MuJoCo's qpos)
template <typename F>
void EachBody(const Body& b, F f) {
  f(b);
  for (const auto& c : b.children) EachBody(*c, f);
}

}  // namespace ohrp::vrml
