// The actuators' command delay: each joint applies the command sent a given number of control
// cycles earlier (a joint file's `delay:`, joint_params.h; hw_emulator's --delay-ms for every
// joint). A ring of preallocated command blocks: SetUp allocates, Shift and Override do not.
#pragma once

#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::model {

class CommandDelay {
 public:
  // joint j delayed by cycles[j] (joints beyond the list: none); the ring holds `initial`
  // (what the actuators apply before the first command arrives). Set-up only.
  void SetUp(const std::vector<int>& cycles, const shm::CommandBlock& initial);
  // the longest delay (0: Shift returns its block unchanged)
  int cycles() const { return ring_.empty() ? 0 : static_cast<int>(ring_.size()) - 1; }
  // enters `now`; returns `now` with each joint's command as entered cycles[j] calls ago
  const shm::CommandBlock& Shift(const shm::CommandBlock& now) noexcept;
  // joint `j` gets `c` in every pending block (what must act at once)
  void Override(int j, const shm::JointCommand& c) noexcept;

 private:
  std::vector<shm::CommandBlock> ring_;  // the longest delay + 1 blocks, ring_[head_] the oldest
  std::vector<int> cycles_;
  shm::CommandBlock out_{};
  size_t head_ = 0;
};

}  // namespace ohrp::model
