// sim_host's fall watch: the simulated robot's ground truth judged once per control cycle; a
// fall is a failure of the run (issue 28 item 1), never "completed".
//
// A fall is the first of (criteria from the robot model, no robot's constants):
//   - contact: a geom of a robot body other than the feet touches the ground: any static geom
//     of the scene that collides with something (floor, stairs, ramps, stones, height fields;
//     a geom with contype = conaffinity = 0 is decoration). The feet are the bodies that carry
//     the soles (sim_host's soles: --soles, or every box geom named *_SOLE, the convention of
//     model::FindSoles) and their subtrees; bodies listed with --fall-allow-contact (e.g. the
//     hands), with their subtrees, may touch too. The robot's geoms are tested whether or not
//     MuJoCo collides them (HRP-1S's links are visual only: they would sink through the floor
//     unseen), with MuJoCo's own narrow phase (mjCOLLISIONFUNC) after a bounding test;
//   - height: the base's height above the lowest point of the soles falls below
//     kFallHeightFraction of that height at the start (the keyframe): a robot whose pelvis is
//     that low over its feet is sitting, kneeling or lying, whatever its leg length;
//   - tilt: the base's vertical has turned more than kFallTiltDeg from where it pointed at the
//     start (the start's posture is upright, whatever the base frame's own axes).
// A robot without soles: no contact test (its feet are unknown; said once); the height is taken
// above the lowest point of its geoms at the start (a level ground assumed). A robot with no
// free joint (or whose joints are not below the free body MapRobot took as its base: a ball
// beside a fixed arm), or one held to the world by an active weld or connect equality (a
// harness, e.g. scenarios/scenes/h1_hung.xml), cannot fall: the watch is off, and says why once.
//
// Cost: the pairs (robot geom, ground geom) are listed at set-up; per cycle a plane or height
// field is a dot product per robot geom, other ground geoms a bounding-sphere test, and only a
// pair that passes goes to the narrow phase. No allocation, no logging in Check. Measured
// (tests/sim_host/fall_watch_test.cc): 4.2 us a check for HRP-1S on scene_rough.xml's 26 ground
// geoms (1248 pairs), against about 100 us of physics per 5 ms control cycle.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

// What the run does at a fall: kEnd stops it at once (exit code kExitFell), kContinue keeps
// simulating (the fall is recorded and the run still exits kExitFell).
enum class OnFall { kEnd, kContinue };
bool ParseOnFall(const std::string& name, OnFall* out);
const char* OnFallName(OnFall on_fall);

struct FallOptions {
  OnFall on_fall = OnFall::kEnd;
  std::vector<std::string> allow_contact;  // bodies (and their subtrees) that may touch the ground
};

// The base above the feet below this fraction of its height at the start is a fall: half the
// stance height is below any stance the legs can carry (a deep squat keeps the pelvis above
// about 60 % of the standing height) and above a robot sitting or lying on the ground.
inline constexpr double kFallHeightFraction = 0.5;
// The base's vertical turned past this from the start is a fall. No standing or walking posture
// tilts a humanoid's pelvis this far (bows and leans stay within about 30 deg, with the trunk
// joints doing the rest); past it the centre of mass of the body above the base lies at
// sin(60 deg) = 0.87 of its height beside the base, outside any stance of the feet. It is the
// backstop of the contact test, for robots whose links do not reach the ground while falling
// (e.g. caught by an obstacle).
inline constexpr double kFallTiltDeg = 60;

enum class FallKind { kNone, kContact, kHeight, kTilt };
const char* FallKindName(FallKind kind);

// The first fall of a run.
struct FallRecord {
  FallKind kind = FallKind::kNone;
  double time = 0;          // [s] simulated, the end of the cycle that saw it
  uint64_t cycle = 0;
  int body = -1;            // kContact: the robot's body that touched
  int geom = -1;            // kContact: its geom
  int ground = -1;          // kContact: the static geom it touched
  double depth = 0;         // [m] kContact: how far into the ground
  double height = 0;        // [m] the base above the feet at that cycle
  double tilt = 0;          // [deg] the base's tilt from the start at that cycle
  char cause[256] = "";     // one sentence (written without allocation)
};

// The watch and its fall as the report and the summary give them (FallWatch::Summary).
struct FallSummary {
  bool on = false;          // the watch ran
  std::string watch;        // FallWatch::Describe
  double start_height = 0;  // [m]
  double min_height = 0;    // [m]
  double max_tilt = 0;      // [deg]
  bool fell = false;
  FallRecord record;        // when fell
  std::string body, geom, ground;  // kContact: names (body, its geom, the ground geom)
  std::string cause;        // record.cause
};

class FallWatch {
 public:
  // Sets the criteria up on the initial state `d` (after the keyframe; not modified). `soles`:
  // the sole geoms' names (empty: model::FindSoles's). False with `*error` when a body of
  // `allow_contact` is not a body of the robot.
  static std::unique_ptr<FallWatch> Create(const mjModel* m, const mjData* d, const model::RobotMap& robot,
                                           const std::vector<std::string>& soles,
                                           const FallOptions& options, std::string* error);

  bool on() const { return on_; }
  // what is watched and with which limits, or why nothing is (one line)
  const std::string& Describe() const { return description_; }

  // Once per control cycle, after its physics steps. True only on the cycle the first fall is
  // seen (recorded in fall()); nothing is done once the robot has fallen. No allocation.
  bool Check(const mjModel* m, const mjData* d, double time, uint64_t cycle);
  bool fell() const { return fall_.kind != FallKind::kNone; }
  const FallRecord& fall() const { return fall_; }

  // the watch and its fall for the report (allocates: after the run)
  FallSummary Summary(const mjModel* m) const;

  double start_height() const { return h0_; }  // [m] the base above the feet at the start
  double min_height() const { return kFallHeightFraction * h0_; }
  size_t pairs() const { return pairs_.size(); }

 private:
  struct Pair {
    int robot_geom, ground_geom;
    mjfCollision collide;  // MuJoCo's narrow phase for the two types (lower type first)
    bool swapped;          // the ground geom's type is the lower: it goes first
  };
  FallWatch() = default;
  double FeetHeight(const mjModel* m, const mjData* d) const;
  bool Touching(const mjModel* m, const mjData* d, const Pair& p, double* depth);

  bool on_ = false;
  std::string description_;
  int base_ = -1;
  std::vector<int> soles_;     // geom ids
  double floor0_ = 0;          // [m] no soles: the lowest point of the robot at the start
  double h0_ = 0;              // [m] base above the feet at the start
  double up0_[3] = {0, 0, 1};  // the world's vertical in the base frame at the start
  double cos_tilt_ = 0.5;
  std::vector<Pair> pairs_;
  std::vector<mjContact> contacts_;  // the narrow phase's scratch (mjMAXCONPAIR)
  FallRecord fall_;
};

// The lowest world height of geom `g` in state `d`: exact for spheres, capsules, cylinders,
// boxes and ellipsoids, the bounding sphere's for other types.
double GeomLowestPoint(const mjModel* m, const mjData* d, int g);

}  // namespace ohrp::sim
