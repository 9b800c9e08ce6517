// The collision geometry of a robot from its MuJoCo model (library ohrp::collision_mjcf, which
// links MuJoCo; the checker itself does not).
#pragma once

#include <mujoco/mujoco.h>

#include <span>
#include <string>

#include "collision/geometry.h"
#include "robot_model/model.h"

namespace ohrp::collision {

// Fills `*out` with the robot's links (its bodies: the base's subtree, the base as the root at
// the origin), their joints by joint id (the segment's actuated joints, then its passive ones:
// RobotGeometry), and every geom of each body: spheres, capsules, cylinders, boxes, ellipsoids,
// and meshes as their convex hulls (MuJoCo's hull graph, or Qhull's). A joint's reference
// position (ref) is folded into its body's pose, so a posture is MuJoCo's qpos of the joints
// (PostureFromQpos). A body below a ball joint (Cassie's achilles rods: the segment does not
// publish a ball joint's orientation) is left out with its subtree and named in
// `out->unchecked`. Returns false and sets `*error` naming the body, joint or geom when the model
// has what the checker cannot take: a free joint below the base, a slide without a range, a
// plane or height field geom, a mesh without a convex hull.
bool GeometryFromModel(const mjModel* m, const model::RobotMap& robot, RobotGeometry* out,
                       std::string* error);

// The posture of the geometry (actuated joints, then passive ones; NumJoints values) from a
// MuJoCo qpos of the model (mjData::qpos, mjModel::qpos0, a keyframe's key_qpos row).
void PostureFromQpos(const model::RobotMap& robot, const mjtNum* qpos, std::span<double> q);

}  // namespace ohrp::collision
