// The controller's self-collision guard as sim_host sees it (see guard_watch.h).
#include "sim_host/guard_watch.h"

#include <algorithm>
#include <cstdio>

namespace ohrp::sim {

int GuardWatch::Update(const shm::GuardRecord& g, double time, uint64_t cycle, int64_t* index) {
  controller_holds_ = g.holds;
  const bool now = g.holding != 0;
  const bool kept = !holds_.empty() && episodes_ <= kMaxGuardHolds;
  *index = kept ? static_cast<int64_t>(holds_.size() - 1) : static_cast<int64_t>(kMaxGuardHolds);
  if (now) {
    ++held_cycles_;
    if (!holding_) {
      holding_ = true;
      ++episodes_;
      if (holds_.size() >= kMaxGuardHolds) {
        *index = static_cast<int64_t>(kMaxGuardHolds);
        return +1;
      }
      GuardHold h;
      h.begin = time;
      h.begin_cycle = cycle;
      // the names are NUL-terminated within kNameLen (the bridge enforces it)
      std::snprintf(h.pair, sizeof(h.pair), "%.*s/%.*s", shm::kNameLen, g.link_a, shm::kNameLen,
                    g.link_b);
      h.distance = h.closest = g.distance;
      h.cycles = 1;
      holds_.push_back(h);
      *index = static_cast<int64_t>(holds_.size() - 1);
      return +1;
    }
    if (kept) {
      GuardHold& h = holds_.back();
      ++h.cycles;
      h.closest = std::min(h.closest, g.distance);
    }
    return 0;
  }
  if (!holding_) return 0;
  holding_ = false;
  if (kept) {
    holds_.back().end = time;
    holds_.back().end_cycle = cycle;
  }
  return -1;
}

GuardSummary GuardWatch::Summary() const {
  GuardSummary s;
  s.episodes = episodes_;
  s.held_cycles = held_cycles_;
  s.controller_holds = controller_holds_;
  s.holding_at_end = holding_;
  s.holds = holds_;
  for (size_t i = 0; i < holds_.size(); ++i)
    if (s.closest < 0 || holds_[i].closest < holds_[s.closest].closest) s.closest = static_cast<int>(i);
  return s;
}

}  // namespace ohrp::sim
