// The collision geometry of a robot from its MuJoCo model (library ohrp::collision_mjcf, which
// links MuJoCo; the checker itself does not).
#pragma once

#include <mujoco/mujoco.h>

#include <string>

#include "collision/geometry.h"
#include "robot_model/model.h"

namespace ohrp::collision {

// Fills `*out` with the robot's links (its bodies: the base's subtree, the base as the root at
// the origin), their hinges by segment joint id, and every geom of each body: spheres,
// capsules, cylinders, boxes, and meshes as their convex hulls (MuJoCo's hull graph). Returns
// false and sets `*error` naming the body or geom when the model has what the checker cannot
// take: a body with more than one joint or a slide or ball joint, a hinge without a motor, a
// hinge whose zero angle is not the model's reference, a plane, height field or ellipsoid geom,
// a mesh without a convex hull.
bool GeometryFromModel(const mjModel* m, const model::RobotMap& robot, RobotGeometry* out,
                       std::string* error);

}  // namespace ohrp::collision
