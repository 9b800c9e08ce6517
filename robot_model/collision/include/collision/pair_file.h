// The self-collision file: what the offline tool (ohrp_selfcollision) found and what a
// controller loads to check its postures online without MuJoCo. YAML (docs/selfcollision.md):
//
//   robot: hrp1s                  # the model's name, and its hash (robot_model/model_hash.h)
//   model_hash: "0x1234abcd..."   # a controller refuses a file of another robot
//   margin: 0.01                  # [m] pairs closer than this stop the motion
//   joints: [{name: WAIST_P, min: -0.5236, max: 1.0472}, ...]        # segment order [rad]
//   passive_joints: [{name: left-shin, min: -0.349, max: 0.349}, ...]  # optional: joints no
//                                 # actuator drives (segment's passive order), ids after joints:
//   unchecked: ["left-achilles-rod: a ball joint ..."]   # optional: bodies left out, never checked
//   links: [{name: WAIST, parent: -1, pos: [x,y,z], quat: [w,x,y,z], joint: -1,
//            axis: [x,y,z], anchor: [x,y,z],
//            shapes: [{type: box, size: [hx,hy,hz], pos: [..], quat: [..]}]}, ...]
//            (types: box, sphere, capsule, cylinder, ellipsoid (size: semi-axes), convex)
//   online: [[LLEG_KNEE, RLEG_KNEE], ...]     # the reduced list: checked every cycle
//   safe_ranges:                              # while each joint keeps to its range, its
//     - {joint: LARM_SHOULDER_R, min: .., max: .., pairs: [[A, B], ...]}   # pairs need no check
//   structural: [[A, B], ...]                 # touching in the model's zero posture: skipped
//   structural_floor: [-0.012, ...]           # [m] per structural pair, the distance it keeps
//   never: [[A, B], ...]                      # apart anywhere in the limits: skipped
//   checksum: "0x..."                         # FNV-1a 64 of the text above: the last line
//
// Convex shapes carry `vertices: [[x,y,z], ...]` and `faces: [n, i, j, k, ...]` (FCL's).
#pragma once

#include <string>
#include <vector>

#include "collision/geometry.h"

namespace ohrp::collision {

// a joint range inside which some pairs cannot collide
struct SafeRange {
  int joint = -1;            // joint id (actuated, or passive: RobotGeometry)
  double lo = 0, hi = 0;     // [rad]
  std::vector<LinkPair> pairs;  // the pairs it prunes (checked online when the joint leaves it)
};

// What a joint can do, for the online guard's braking check (controllers/self_collision_guard.h):
// written by ohrp_selfcollision from the model (collision/joint_dynamics.h), by segment joint id.
// The torque limit is not here: the guard takes the producer's (SegmentHeader::tau_max).
struct JointDynamics {
  double inertia_max = 0;   // [kg m^2] upper bound of the inertia the joint's torque drives, in
                            // any posture: reflected rotor inertia (armature) plus the larger of
                            // the links beyond the joint and the rest of the robot about its axis
  double inertia_min = 0;   // [kg m^2] lower bound of the same (at least the armature)
  double gravity_max = 0;   // [N m] bound of the gravity torque about the joint, any posture
  double damping = 0;       // [N m s/rad] the joint's passive damping
  double velocity_max = 0;  // [rad/s] the joint's speed limit where the model or robot profile
                            // states one, else 0 (none known)
  double inertia_free = 0;  // [kg m^2] the same bound for the links beyond alone (armature
                            // included): what the joint drives while they carry no weight
  std::string support_sensor;  // the force sensor beyond the joint that tells when the links
                               // beyond stand on something ("": no foot beyond, inertia_max
                               // always; "none": a foot without a sensor, always loaded)
  double support_force = 0;    // [N] above this force on it, they do (a tenth of the weight)
};

struct SelfCollisionFile {
  RobotGeometry robot;
  double margin = 0.01;  // [m]
  std::vector<LinkPair> online, structural, never;
  // per structural pair (same order): the signed distance it must keep [m] (built-in overlap at
  // the zero or reference posture, less a tolerance); empty in a file without floors
  std::vector<double> structural_floor;
  std::vector<SafeRange> ranges;
  std::vector<JointDynamics> dynamics;  // by segment joint id; empty in a file without them
};

// What is wrong with a file's lists (ValidateSelfCollisionFile): the key, the item of its list
// (-1: the key itself) and what, with what would work.
struct FileProblem {
  std::string key;
  int item = -1;
  std::string what;
};

// The lists of a file against its own geometry: every non-adjacent pair (NonAdjacentPairs) in
// exactly one of online, structural and never, or in the pairs of one or more safe ranges; no
// pair twice in a list, none that is not a non-adjacent pair; each safe range's joint between
// its pairs' links, the range inside the joint's limits and narrower than them (a range covering
// the whole joint restricts nothing: its pairs are never pairs), one range per joint; a floor for
// each structural pair when floors are given. False with `*problem` at the first mistake.
bool ValidateSelfCollisionFile(const SelfCollisionFile& file, FileProblem* problem);

// The checksum line the writer appends to the text `body` ("checksum: \"0x...\"\n", FNV-1a 64
// of `body`), and the check of a whole text: true when its last line is the checksum of the
// text before it; else false with `*what` (missing, or the text was edited) and `*line`.
std::string ChecksumLine(const std::string& body);
bool ChecksumMatches(const std::string& text, int* line, std::string* what);

// Writes `file` to `path` as YAML. False with `*error` when it cannot be written.
bool WriteSelfCollisionFile(const std::string& path, const SelfCollisionFile& file,
                            std::string* error);

// The YAML text of `file` (what WriteSelfCollisionFile writes), its checksum line last.
std::string SelfCollisionYaml(const SelfCollisionFile& file);

// Reads a file written by WriteSelfCollisionFile. False with `*error` as
// "path:line: key: what is wrong (what would work)" on any mistake: a missing or unknown key, a
// value of the wrong kind, an unknown link or joint name, a geometry that Validate refuses, lists
// that ValidateSelfCollisionFile refuses, a checksum that is missing or does not match the text
// (edited by hand).
bool ReadSelfCollisionFile(const std::string& path, SelfCollisionFile* file, std::string* error);

}  // namespace ohrp::collision
