// The self-collision file: what the offline tool (ohrp_selfcollision) found and what a
// controller loads to check its postures online without MuJoCo. YAML (docs/selfcollision.md):
//
//   robot: hrp1s                  # the model's name, and its hash (robot_model/model_hash.h)
//   model_hash: "0x1234abcd..."   # a controller refuses a file of another robot
//   margin: 0.01                  # [m] pairs closer than this stop the motion
//   joints: [{name: WAIST_P, min: -0.5236, max: 1.0472}, ...]        # segment order [rad]
//   links: [{name: WAIST, parent: -1, pos: [x,y,z], quat: [w,x,y,z], joint: -1,
//            axis: [x,y,z], anchor: [x,y,z],
//            shapes: [{type: box, size: [hx,hy,hz], pos: [..], quat: [..]}]}, ...]
//   online: [[LLEG_KNEE, RLEG_KNEE], ...]     # the reduced list: checked every cycle
//   safe_ranges:                              # while each joint keeps to its range, its
//     - {joint: LARM_SHOULDER_R, min: .., max: .., pairs: [[A, B], ...]}   # pairs need no check
//   structural: [[A, B], ...]                 # touching in the model's zero posture: skipped
//   never: [[A, B], ...]                      # apart anywhere in the limits: skipped
//
// Convex shapes carry `vertices: [[x,y,z], ...]` and `faces: [n, i, j, k, ...]` (FCL's).
#pragma once

#include <string>
#include <vector>

#include "collision/geometry.h"

namespace ohrp::collision {

// a joint range inside which some pairs cannot collide
struct SafeRange {
  int joint = -1;            // segment joint id
  double lo = 0, hi = 0;     // [rad]
  std::vector<LinkPair> pairs;  // the pairs it prunes (checked online when the joint leaves it)
};

struct SelfCollisionFile {
  RobotGeometry robot;
  double margin = 0.01;  // [m]
  std::vector<LinkPair> online, structural, never;
  std::vector<SafeRange> ranges;
};

// Writes `file` to `path` as YAML. False with `*error` when it cannot be written.
bool WriteSelfCollisionFile(const std::string& path, const SelfCollisionFile& file,
                            std::string* error);

// The YAML text of `file` (what WriteSelfCollisionFile writes).
std::string SelfCollisionYaml(const SelfCollisionFile& file);

// Reads a file written by WriteSelfCollisionFile. False with `*error` as
// "path:line: key: what is wrong (what would work)" on any mistake: a missing or unknown key, a
// value of the wrong kind, an unknown link or joint name, a geometry that Validate refuses.
bool ReadSelfCollisionFile(const std::string& path, SelfCollisionFile* file, std::string* error);

}  // namespace ohrp::collision
