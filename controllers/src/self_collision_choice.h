// Which self-collision file a controller's runner loads for the segment's robot.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "controllers/runner.h"
#include "shm_bridge/layout.h"

namespace ohrp::controllers {

// The `self_collision:` files of the robot profiles in robots/ of the data folder (sorted).
std::vector<std::string> ProfileSelfCollisionFiles();

// The file to load ("" for none): the one given (--self-collision); when none was given, the
// profile file made for this very model (the segment's model hash), else the default
// (HRP-1S's), which for another robot, or a producer that publishes no model hash, means no
// check, said on `err` as a WARNING. A default for this robot but another model is returned: the
// guard refuses it (exit 3), protection is never silently off.
std::string SelfCollisionFileFor(const RunOptions& options, const shm::SegmentHeader& header,
                                 const std::string& prog, std::ostream& err);

}  // namespace ohrp::controllers
