// The walk's live commands (see walk.h, LiveCycle; the channel: walk_channel.h).
#include <unistd.h>

#include "controllers/walk.h"

namespace ohrp::controllers {
namespace {

constexpr int kLiveSteps = 10000;  // room for a live command's steps (the gait's and the swap's)

}  // namespace

ConfigStatus WalkController::OpenChannel() {
  if (!walk_options_.listen && walk_options_.socket.empty()) return ConfigStatus::Ok();
  // what the cycle needs for the largest plan, allocated now
  gen_.Reserve(gen_.gait().step_count() + walk_stats_.steps_planned + kLiveSteps + 8);
  live_steps_.reserve(kLiveSteps);
  LivePlanning planning;
  planning.limits = walk_options_.limits;
  planning.step_time = walk_options_.gait.step_time;
  planning.max_steps = kLiveSteps;
  channel_ = std::make_unique<WalkChannel>();
  std::string error;
  if (!channel_->Open(walk_options_.listen ? STDIN_FILENO : -1, walk_options_.socket, planning, &error)) {
    channel_.reset();
    return ConfigStatus::Fail(ConfigError::kOption, error);
  }
  return ConfigStatus::Ok();
}

void WalkController::LiveCycle() noexcept {
  if (!channel_) return;
  const walking::Gait& gait = gen_.gait();
  const int k = gait.StartedBy(gen_.sample().t);
  if (k != live_started_) {  // a step has begun: the stance a new command starts from moved on
    live_started_ = k;
    ++live_version_;
  }
  channel_->Publish(gait.FeetAfter(k), live_version_);
  switch (channel_->Poll(live_version_, &live_steps_)) {
    case WalkChannel::Got::kNothing:
      return;
    case WalkChannel::Got::kStop:
      Stop();
      break;
    case WalkChannel::Got::kSteps:
      // what was planned after the step under way gives way; the commands given at the start
      // are dropped, and the live steps, planned in the plan frame, are not remapped
      next_command_ = static_cast<int>(chunks_plan_.size());
      chunk_ = -1;
      gen_.Replace(live_steps_);
      walk_stats_.stopped = false;
      ++walk_stats_.commands_done;
      break;
  }
  walk_stats_.steps_planned = gait.step_count();
  ++live_version_;
}

}  // namespace ohrp::controllers
