// What each joint of a robot can do, from its MuJoCo model (library ohrp::collision_mjcf): the
// bounds of the inertia its torque drives and of the gravity torque it holds, valid in any
// posture, for the online guard's braking check (controllers/self_collision_guard.h). Written
// into the self-collision file (collision/pair_file.h: `dynamics:`) by ohrp_selfcollision.
//
// For joint j with axis through anchor A (its body's frame), every body b has its centre of mass
// within r_b of A in any posture: the chain of body offsets between them (|body_pos| plus twice
// each hinge's anchor offset |jnt_pos| of the bodies on the way, a slide's travel) plus the
// body's own |ipos|. The inertia of a set S of bodies about the axis is then at most
// sum_{b in S} m_b r_b^2 + I_b,max (its largest principal inertia), and its gravity torque at most
// |g| sum_{b in S} m_b r_b. The sets: the links beyond the joint (what MuJoCo's qM diagonal
// holds for a floating robot) and, where the links beyond include a support, the rest of the
// robot (what the joint drives when the links beyond stand on the ground: a hip with its foot
// planted turns the torso); the larger is kept. Supports (SupportBodies): the bodies the robot
// stands on in the model's initial posture, the lowest tenth of its height. A robot leaning on a
// hand is outside these bounds: its arm joints would drive the body.
#pragma once

#include <mujoco/mujoco.h>

#include <vector>

#include "collision/pair_file.h"
#include "robot_model/model.h"

namespace ohrp::collision {

// Per segment joint (robot.joints order): inertia_max = armature + the larger bound above;
// inertia_min = the armature (a lower bound of the effective inertia in any posture and under
// any contact: M >= armature e_j e_j^T), or, for a joint without armature, the sum of the
// smallest principal inertias of the links beyond (a lower bound of qM's diagonal);
// gravity_max the larger gravity bound above; damping = dof_damping; velocity_max = 0 (MJCF
// states no speed limit); inertia_free = armature + the bound of the links beyond alone; for a
// joint whose links beyond include a support and a force sensor (robot.forces), that sensor and
// a tenth of the robot's weight: while it reads less, the links beyond carry no weight and the
// joint drives them alone; with a support but no force sensor, the sensor "none" (the guard
// then takes the leg as always loaded: never braked, the inertia under any contact).
std::vector<JointDynamics> JointDynamicsFromModel(const mjModel* m, const model::RobotMap& robot);

// By MuJoCo body id: 1 for the robot's bodies whose geoms' bounding spheres reach into the lowest
// tenth of its height in the model's initial posture (qpos0): its feet.
std::vector<char> SupportBodies(const mjModel* m, const model::RobotMap& robot);

}  // namespace ohrp::collision
