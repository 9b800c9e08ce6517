// The online self-collision check of every controller (the paper's section 4.1, step 3): before
// a cycle's commands are written, the commanded posture and the one a cycle ahead (the
// commanded velocities over one control period) are checked against the reduced pair list of a
// self-collision file (ohrp_selfcollision; docs/selfcollision.md), plus the pairs of each safe
// range the posture leaves. A pair closer than the file's margin that is closer than in the
// last safe references (or penetrating) stops the motion: every joint holds the last safe
// references (velocity 0), the cycle is counted, and the report after the run names the pair.
// Moving away from a close pair is allowed; once holding, only a command within kResumeStep of
// the held references resumes (a far one could pass through a link).
//
// Configure reads the file and checks it against the segment's header (model hash, joint
// names); Filter runs every cycle and allocates, throws and logs nothing. No MuJoCo: the file
// carries the links' geometry. A pair whose last measured distance exceeds the margin by more
// than its two links can have moved since is not measured again (collision::IncrementalCheck):
// the answer within the margin is the full check's, at a fraction of its cost while moving.
#pragma once

#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "collision/incremental_check.h"
#include "collision/pair_file.h"
#include "collision/self_collision.h"
#include "shm_bridge/layout.h"

namespace ohrp::controllers {

class SelfCollisionGuard {
 public:
  // Reads `path` and checks it against `header`. Returns an empty string when the guard is
  // ready, else why not (the file's own message with file:line, or the robot it is for).
  std::string Configure(const std::string& path, const shm::SegmentHeader& header);

  // The robot the file describes matches the header's model (for a default file that may not
  // be meant for this robot: the caller then turns the check off).
  static bool FileMatches(const std::string& path, const shm::SegmentHeader& header);

  // Starts from the measured posture (the first safe references).
  void Activate(const shm::SensorBlock& sensors);

  // Checks `commands` (position references of position-mode joints, measured angles of the
  // others) and, one period ahead, with the velocity references; holds the last safe
  // references when a pair comes closer than the margin. Returns true when it held.
  bool Filter(const shm::SensorBlock& sensors, shm::CommandBlock* commands);

  // The counts and the first and closest pairs, one paragraph; nothing when nothing happened.
  void Report(const std::string& program, std::ostream& out) const;

  long held_cycles() const { return held_cycles_; }
  // [judge, issue 29: minimal stand-ins from today's members, for the segment's guard record;
  // the guard's rework replaces them] holding: the last Filter held; holds: hold episodes
  // begun (not counted by today's Filter: 0); the pair and its predicted distance [m]
  bool holding() const { return holding_; }
  uint64_t holds() const { return 0; }
  collision::LinkPair hold_pair() const { return closest_pair_; }
  double hold_distance() const { return closest_distance_; }
  // [end judge]
  const collision::SelfCollisionFile& file() const { return file_; }

 private:
  // the closest pair of the reduced list at posture q (-1: none within the margin)
  collision::CheckResult Closest(const std::vector<double>& q);

  collision::SelfCollisionFile file_;
  std::unique_ptr<collision::SelfCollision> checker_;
  int njoint_ = 0;
  double period_ = 0;                        // [s]
  std::unique_ptr<collision::IncrementalCheck> check_;  // over every_
  std::vector<int> list_;                    // this cycle's pairs, indices into every_
  std::vector<std::vector<int>> range_pairs_;  // per safe range, its pairs' indices in every_
  std::vector<char> on_list_;                // per online-or-pruned pair index, this cycle
  std::vector<collision::LinkPair> every_;   // the online pairs then each range's pairs
  std::vector<double> q_, q_ahead_, safe_;   // [rad]
  std::vector<double> last_q_;               // the posture checked last cycle [rad]
  collision::CheckResult last_now_;          // and its answer
  double safe_distance_ = 0;                 // [m] of the last safe references
  bool holding_ = false;                     // the last cycle held
  static constexpr double kResumeStep = 0.05;  // [rad] a held command resumes within this
  long held_cycles_ = 0;
  double first_time_ = -1, closest_distance_ = 1e9, first_distance_ = 0;  // [s], [m]
  collision::LinkPair first_pair_, closest_pair_;
};

}  // namespace ohrp::controllers
