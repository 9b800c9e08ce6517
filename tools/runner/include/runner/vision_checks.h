// Checks on what a camera sees, computed from the poses in sim_host's data log, never from
// images or from a controller's own estimate:
//   ball_centred  a geom's centre (e.g. the red ball of scene_ball.xml), projected by a
//                 pinhole camera at a camera's pose, lies within `tolerance` pixels of the
//                 image's centre.
// The camera's pose is the scene's kinematics (the scene of sim_host's summary) at the logged
// base pose (base_x..base_qz) and joint angles (q_<joint>); the projection is MuJoCo's camera
// convention (looking along -z, y up) with the camera's vertical field of view fovy and a
// width x height image: u = W/2 + f x/(-z), v = H/2 - f y/(-z), f = (H/2) / tan(fovy/2), the
// point (x, y, z) in the camera frame, pixel centres at +0.5. Keys: runner/check_keys.h.
#pragma once

#include <nlohmann/json.hpp>

#include "runner/checks.h"

namespace ohrp::runner {

// The pixel (u, v) at which a pinhole camera (focal length `f` [pixel], image `width` x
// `height`) sees the point `p_C` of its frame (MuJoCo's: x right, y up, looking along -z);
// false when the point is not in front of the camera.
bool ProjectPinhole(const double p_C[3], double f, int width, int height, double* u, double* v);

CheckResult BallCentred(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim);

}  // namespace ohrp::runner
