// The actuators' command delay (command_delay.h).
#include "robot_model/command_delay.h"

#include <algorithm>

namespace ohrp::model {

void CommandDelay::SetUp(const std::vector<int>& cycles, const shm::CommandBlock& initial) {
  cycles_.assign(cycles.begin(), cycles.begin() + std::min<size_t>(cycles.size(), shm::kMaxJoints));
  const int longest = cycles_.empty() ? 0 : *std::max_element(cycles_.begin(), cycles_.end());
  ring_.clear();
  if (longest > 0) ring_.assign(static_cast<size_t>(longest) + 1, initial);
  head_ = 0;
}

const shm::CommandBlock& CommandDelay::Shift(const shm::CommandBlock& now) noexcept {
  if (ring_.empty()) return now;
  const size_t n = ring_.size();
  ring_[head_] = now;
  out_ = now;
  for (size_t j = 0; j < cycles_.size(); ++j)
    out_.joint[j] = ring_[(head_ + n - static_cast<size_t>(cycles_[j])) % n].joint[j];
  head_ = (head_ + 1) % n;
  return out_;
}

void CommandDelay::Override(int j, const shm::JointCommand& c) noexcept {
  for (shm::CommandBlock& b : ring_) b.joint[j] = c;
}

}  // namespace ohrp::model
