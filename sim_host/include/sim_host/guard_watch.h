// The controller's self-collision guard as sim_host sees it (issue 29: holds are results). Each
// command block carries the guard's record (shm::GuardRecord: holding this cycle, the pair and
// its predicted distance); GuardWatch turns the records into hold episodes (a hold begins when
// `holding` goes from 0 to 1 and ends when it goes back), for the run's events
// ("guard_hold_begin" / "guard_hold_end", value: the episode's index in the summary's list),
// the summary's "self_collision_guard" and the end-of-run line. Update allocates, throws and
// logs nothing (the episodes' capacity is reserved; more are counted, not kept).
#pragma once

#include <cstdint>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::sim {

inline constexpr size_t kMaxGuardHolds = 1024;  // episodes kept per run; more are counted

// one hold episode
struct GuardHold {
  double begin = 0;           // simulated time of its first held cycle [s]
  uint64_t begin_cycle = 0;
  double end = -1;            // time of the first cycle no longer held [s]; -1: held to the end
  uint64_t end_cycle = 0;
  char pair[2 * shm::kNameLen + 2] = {};  // "LINK_A/LINK_B" as the guard named it at the begin
  double distance = 0;        // the pair's predicted distance at the begin [m]
  double closest = 0;         // the smallest distance the guard gave during the episode [m]
  uint64_t cycles = 0;        // command blocks held
};

struct GuardSummary {
  uint64_t episodes = 0;          // hold episodes begun (kept or not)
  uint64_t held_cycles = 0;       // command blocks the guard held
  uint64_t controller_holds = 0;  // the controller's own count (GuardRecord::holds, its last)
  bool holding_at_end = false;    // the last command block was held
  std::vector<GuardHold> holds;   // the first kMaxGuardHolds episodes
  int closest = -1;               // index into holds of the closest distance, -1: none
};

class GuardWatch {
 public:
  GuardWatch() { holds_.reserve(kMaxGuardHolds); }

  // The record of the command block that answers cycle `cycle` (simulated time `time`).
  // Returns +1 when a hold began with it, -1 when one ended, 0 otherwise; `*index` is the
  // episode's index in the list (or kMaxGuardHolds when it was not kept).
  int Update(const shm::GuardRecord& g, double time, uint64_t cycle, int64_t* index);

  GuardSummary Summary() const;

 private:
  std::vector<GuardHold> holds_;
  uint64_t episodes_ = 0, held_cycles_ = 0, controller_holds_ = 0;
  bool holding_ = false;
};

}  // namespace ohrp::sim
