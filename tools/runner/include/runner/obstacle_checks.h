// The robot's contacts with and clearance from the scene's static obstacles, measured on the
// simulated motion
// (issue 34 item 3): independent of any planner. The run's data log (the simulated base pose
// and joint angles of every logged cycle) replayed through the scene's own MuJoCo model: each
// of the robot's geoms against each static geom of the scene (a geom welded to the world, not a
// plane or height field: the floor is where the feet stand), with MuJoCo's own collision
// functions (no margin: penetration only; MuJoCo 2.2's box-box function misreports the distance
// of boxes apart when given a margin) for pairs whose bounding spheres overlap.
#pragma once

#include <nlohmann/json.hpp>

#include "runner/checks.h"

namespace ohrp::runner {

// `obstacle_contacts`: the logged cycles in which a robot geom penetrates a static obstacle are
// at most `max` (default 0). The detail names the first contact and the deepest.
CheckResult ObstacleContacts(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim);

// `obstacle_clearance`: the smallest signed distance [m] of a robot geom to a static obstacle
// over the logged cycles is at least `min` (default 0): the distance the simulated robot kept,
// not the plan's. Distances by the self-collision checker's certified measurement
// (collision/shape_distance.h: GJK checked by the projections' gap, never more than the true
// gap; an overlap as minus its depth), meshes as their hulls; only pairs whose bounding spheres
// come closer than both the limit and the closest so far are measured, so none is missed. The
// detail names the closest pair and when, and the cycles below the limit.
CheckResult ObstacleClearance(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim);

}  // namespace ohrp::runner
