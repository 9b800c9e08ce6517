// The robot model's identity: a hash of the robot's kinematic tree and inertias that the
// producer publishes in the segment header (SegmentHeader::model_hash), so that a controller
// which loads its own copy of the MJCF refuses to run against a producer whose robot differs,
// with a message naming the first difference it can see.
//
// What is hashed (FNV-1a 64, shm::Fnv1a64): for each body of the robot, in MuJoCo's body order
// (depth first), its parent (as an index among the robot's bodies, -1 for the root), its pose in
// the parent (pos, quat; skipped for a body with a free joint: that is an initial condition, not
// part of the robot), its mass, diagonal inertia and inertial frame (ipos, iquat), and each of its
// joints (type, name, axis, pos, limited and range, armature and damping of each dof); then, body
// by body, its geoms, which the self-collision checker takes as the links' shapes
// (collision/from_mjcf.h): their count and each one's type, size, pos, quat and, for a mesh, its
// vertex count and vertices (so a self-collision file made for other shapes no longer fits);
// then the segment's joint order (the names, in joint-id order). Integers are fed as 8 little-endian
// bytes, doubles as their bits after -0.0 is made 0.0, names as their length then their bytes.
// Colours, contact parameters (friction, contype, margins), sensors, the floor and the simulation
// options are not part of it: the same robot on another floor, or with other sole contact parameters, has the
// same hash.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <string>
#include <vector>

#include "robot_model/model.h"
#include "shm_bridge/bridge.h"

namespace ohrp::model {

// The bodies of `robot` in `m`, in MuJoCo's order: the subtree of the base (free-floating
// robot) or every body but the world (fixed robot).
std::vector<int> RobotBodies(const mjModel* m, const RobotMap& robot);

// The hash described above. Deterministic across processes and builds of the same MJCF.
uint64_t ModelHash(const mjModel* m, const RobotMap& robot);

// Fills the model identity fields of `*config` (model_hash, nbody, total_mass, joint_axis,
// link_mass) from `m` and `robot`. MakeProducerConfig calls it.
void FillModelIdentity(const mjModel* m, const RobotMap& robot, shm::ProducerConfig* config);

// Compares the model a controller loaded (`m`, `robot`) with the producer's `header`. Returns an
// empty string when the hashes match. Otherwise returns one message naming the first difference
// found, in this order: the robot name (a note only, scenes name the model), the joint count,
// the joint names (the first that differs, with its id), the joint limits, the joint axes, the
// masses of the joints' bodies, the total mass, the body count; when none of these differ it
// says that the kinematic tree differs (body positions, inertias or passive joints). The
// message always ends with both hashes in hex. A header with model_hash 0 (a producer that
// publishes no identity) is refused too. The header's counts are clamped before use.
std::string CheckModelMatches(const mjModel* m, const RobotMap& robot,
                              const shm::SegmentHeader& header);

}  // namespace ohrp::model
