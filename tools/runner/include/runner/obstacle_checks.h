// The robot's clearance from the scene's static obstacles, measured on the simulated motion
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

}  // namespace ohrp::runner
