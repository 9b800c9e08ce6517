// sim_host's self_collision effect (docs/effects.md, docs/selfcollision.md): the simulated robot's
// link pairs checked once per control cycle with the checker the controllers use
// (robot_model/collision: collision::SelfCollision), so that what the simulation reports and what
// a controller's guard holds agree by construction.
//
// The geometry is built from the simulated model itself (collision::GeometryFromModel: every geom
// of every body of the robot, meshes as their convex hulls), whatever MuJoCo's contype and
// conaffinity say: HRP-1S's links do not collide in MuJoCo (only its soles do), so the effect
// reports where they pass through each other. The pairs:
//   - no file: every pair of links that are not parent and child (collision::NonAdjacentPairs)
//     less those in contact in the model's zero posture (qpos0, as built), in any keyframe of the scene or in the
//     run's initial state (parts built into each other, e.g. HRP-1S's thighs in its waist box at
//     half-sitting): those would be "in contact" all run long;
//   - a file of ohrp_selfcollision (`sim_host --self-collision FILE`): its online pairs and the
//     pairs of its safe ranges (all of them, every cycle: the simulation does not assume the
//     ranges hold), by link name; the file must be for this robot (model hash).
// A pair is in contact when its signed distance is negative (penetration). Per cycle, Check
// reads the joint angles from mjData (actuated and passive joints: collision::PostureFromQpos) and checks the pairs with collision::IncrementalCheck, as
// the controllers' guard does: a pair whose last measured distance exceeds what its two links
// can have moved since is still apart and is not measured again; the others are measured with
// the checker (whose broad phase skips pairs whose bounding spheres are apart). It allocates,
// throws and logs nothing, and runs once per control cycle, outside the physics steps.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "collision/geometry.h"
#include "collision/incremental_check.h"
#include "collision/self_collision.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

// one pair that came into contact during the run
struct SelfCollisionHit {
  std::string pair;          // "LINK_A/LINK_B" (link = MuJoCo body name)
  double first_time = 0;     // simulated time of the first cycle in contact [s]
  uint64_t first_cycle = 0;  // that cycle
  double deepest = 0;        // the deepest penetration seen [m] (> 0)
  double deepest_time = 0;   // when [s]
  uint64_t cycles = 0;       // control cycles in contact
};

// what the effect found, for the end-of-run report and the summary's "self_collision"
struct SelfCollisionSummary {
  bool on = false;
  std::string source;             // "all non-adjacent pairs" or the file
  int links = 0;
  int pairs_checked = 0;
  std::vector<std::string> excluded;  // pairs left out as built into each other (no file)
  uint64_t checks = 0;                // cycles checked
  uint64_t measured = 0;              // pair distances measured (checks x pairs at most: a pair
                                      // that cannot have reached contact is not measured again)
  uint64_t cycles_in_contact = 0;     // of those, cycles with at least one pair in contact
  // the closest approach of any checked pair over the run: its smallest signed distance [m]
  // (negative: the deepest penetration), exact when below kClosestRange; when no pair came
  // that close, a lower bound (closest_exact false) and no pair
  double closest = 0;
  bool closest_exact = false;
  std::string closest_pair;           // "LINK_A/LINK_B", empty when not exact
  double closest_time = 0;            // when [s]
  uint64_t closest_cycle = 0;
  double check_seconds = 0;           // CPU time of the thread in Check, in all [s]
  double check_max = 0;               // the longest Check (CPU time) [s]
  std::vector<SelfCollisionHit> pairs;  // in the order of their first contact
};

class SelfCollisionWatch {
 public:
  // distances at or below this are measured exactly each cycle, for the closest approach [m]
  // (a reporting range, not a threshold: the margins of self-collision files lie well below).
  // Its cost: pairs within it are measured every cycle (HRP-1S's arm swung into the leg: 27 us
  // a check at 20 mm, 75 us at 50 mm, 10 us for contacts only)
  static constexpr double kClosestRange = 0.02;

  // Builds the checker from `m` (as loaded) and the pair list (above). `file` empty: every
  // non-adjacent pair less those in contact at the zero posture and in the scene's keyframes
  // (the initial state is added by Start). Returns null with `*error` naming what is wrong (the
  // model's geometry, the file's own message with its line, a file for another robot).
  static std::unique_ptr<SelfCollisionWatch> Create(const mjModel* m, const model::RobotMap& robot,
                                                    const std::string& file, std::string* error);

  // The run's initial state: without a file, pairs in contact in it are left out too.
  void Start(const mjData* d);

  // Checks the posture of `d` (cycle `cycle`, simulated time `time`); no allocation.
  void Check(const mjData* d, double time, uint64_t cycle);

  // "397 of 406 non-adjacent pairs of 30 links ..." for --explain and the start of a run
  std::string Describe() const;

  SelfCollisionSummary Summary() const;

  const std::vector<collision::LinkPair>& pairs() const { return pairs_; }
  const collision::RobotGeometry& geometry() const { return checker_->robot(); }
  // the pairs in contact at the last Check (indices into pairs()); valid until the next Check
  const std::vector<int>& in_contact() const { return in_contact_; }
  // per pair, its last measured signed distance [m] (a lower bound when apart; exact for the
  // pairs in contact, which are measured every check)
  const std::vector<double>& distances() const { return check_->distances(); }

 private:
  SelfCollisionWatch() = default;
  void ReadPose(const mjData* d);
  std::string PairName(const collision::LinkPair& p) const;
  // drops the pairs in contact at the current pose (SetPose done), recording them as excluded
  void ExcludeTouching(const std::string& where);
  // (re)builds the per-pair state for pairs_ (set-up only)
  void TrackPairs();

  const model::RobotMap* robot_ = nullptr;
  std::unique_ptr<collision::SelfCollision> checker_;
  std::string source_;
  int all_pairs_ = 0;
  bool from_file_ = false;
  std::vector<collision::LinkPair> pairs_;
  std::vector<std::string> excluded_;
  std::unique_ptr<collision::IncrementalCheck> check_;  // over pairs_
  uint64_t measured_ = 0;        // pair measurements made (the others were skipped)
  // per cycle, allocated once
  std::vector<double> q_;
  std::vector<int> in_contact_;
  // per pair
  std::vector<double> first_time_, deepest_, deepest_time_;
  std::vector<uint64_t> first_cycle_, cycles_;
  std::vector<int> order_;  // pair indices in the order of first contact (capacity: all)
  uint64_t checks_ = 0, cycles_in_contact_ = 0;
  double closest_ = 1e9, closest_time_ = 0;  // the run's closest approach [m], [s]
  int closest_pair_ = -1;                    // its pair (index into pairs_), -1: none in range
  uint64_t closest_cycle_ = 0;
  double check_seconds_ = 0, check_max_ = 0;
};

}  // namespace ohrp::sim
