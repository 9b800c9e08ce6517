// The collision geometry of a robot from its MuJoCo model (library ohrp::collision_mjcf, which
// links MuJoCo; the checker itself does not).
#pragma once

#include <mujoco/mujoco.h>

#include <span>
#include <string>

#include "collision/geometry.h"
#include "robot_model/model.h"

namespace ohrp::collision {

// A mesh's convex hull of more vertices than this becomes its outer polytope within
// kMeshHullTolerance [m] (it contains the hull: distances measured on it are at most that much
// shorter, never longer; collision/src/outer_hull.h), when that has fewer vertices
inline constexpr size_t kExactHullVertices = 32;
inline constexpr double kMeshHullTolerance = 0.002;

// Fills `*out` with the robot's links (its bodies: the base's subtree, the base as the root at
// the origin), their joints by joint id (the segment's actuated joints, then its passive ones:
// RobotGeometry), and every geom of each body: spheres, capsules, cylinders, boxes, ellipsoids,
// and meshes as their convex hulls (MuJoCo's hull graph, or Qhull's; a large hull as its outer
// polytope, above). A geom the same as an earlier one of its body (type, mesh, size, pose: a
// visual and a collision geom of one mesh) is taken once. A joint's reference
// position (ref) is folded into its body's pose, so a posture is MuJoCo's qpos of the joints
// (PostureFromQpos). A body below a ball joint (Cassie's achilles rods: the segment does not
// publish a ball joint's orientation) is left out with its subtree and named in
// `out->unchecked`. Returns false and sets `*error` naming the body, joint or geom when the model
// has what the checker cannot take: a free joint below the base, a slide without a range, a
// plane or height field geom, a mesh without a convex hull.
bool GeometryFromModel(const mjModel* m, const model::RobotMap& robot, RobotGeometry* out,
                       std::string* error);

// Geom `g` of `m` as a convex shape, posed in its body (Shape::p_LS, q_LS: the geom's pos and
// quat; a mesh as its hull, as GeometryFromModel takes it). False with `*error` saying why for a
// plane or height field, or a mesh without a convex hull.
bool GeomShape(const mjModel* m, int g, Shape* s, std::string* error);

// The posture of the geometry (actuated joints, then passive ones; NumJoints values) from a
// MuJoCo qpos of the model (mjData::qpos, mjModel::qpos0, a keyframe's key_qpos row).
void PostureFromQpos(const model::RobotMap& robot, const mjtNum* qpos, std::span<double> q);

}  // namespace ohrp::collision
