// The walk's live commands (see walk.h, LiveCycle; the channel: walk_channel.h).
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "controllers/walk.h"
#include "robot_model/output_file.h"

namespace ohrp::controllers {
namespace {

constexpr int kLiveSteps = 10000;  // room for a live command's steps (the gait's and the swap's)

// a --live-record file: "T LINE" per line, T not decreasing; false with *error (file:line: why)
bool ReadLiveRecord(const std::string& path, std::vector<std::pair<double, std::string>>* out,
                    std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "--live-replay " + path + ": cannot read it";
    return false;
  }
  std::string line;
  double last = -INFINITY;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream words(line);
    double t;
    std::string text;
    if (!(words >> t) || !std::isfinite(t) || t < last || !std::getline(words >> std::ws, text) || text.empty()) {
      *error = "--live-replay " + path + ":" + std::to_string(n) + ": \"" + line +
               "\": not 'T LINE' with T [s] not before the line above's";
      return false;
    }
    last = t;
    out->emplace_back(t, text);
  }
  return true;
}

}  // namespace

ConfigStatus WalkController::OpenChannel() {
  if (!walk_options_.live_replay.empty()) {
    if (walk_options_.listen || !walk_options_.socket.empty())
      return ConfigStatus::Fail(ConfigError::kOption, "--live-replay plays a record: not with --socket or --listen");
    std::vector<std::pair<double, std::string>> lines;
    std::string error;
    if (!ReadLiveRecord(walk_options_.live_replay, &lines, &error))
      return ConfigStatus::Fail(ConfigError::kOption, error);
    for (auto& [t, text] : lines) replay_.push_back({t, text});
    replay_taken_.reserve(replay_.size());  // --live-record: what the replay took, when
    gen_.Reserve(gen_.gait().step_count() + walk_stats_.steps_planned + kLiveSteps + 8);
    replay_planning_.limits = walk_options_.limits;
    replay_planning_.step_time = walk_options_.gait.step_time;
    replay_planning_.max_steps = kLiveSteps;
    return ConfigStatus::Ok();
  }
  if (!walk_options_.live_record.empty() && !walk_options_.listen && walk_options_.socket.empty())
    return ConfigStatus::Fail(ConfigError::kOption,
                              "--live-record records live commands: give --socket, --listen or --live-replay");
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
  if (!replay_.empty()) return ReplayCycle();
  if (!channel_) return;
  const walking::Gait& gait = gen_.gait();
  const int k = gait.StartedBy(gen_.sample().t);
  if (k != live_started_) {  // a step has begun: the stance a new command starts from moved on
    live_started_ = k;
    ++live_version_;
  }
  channel_->Publish(gait.FeetAfter(k), live_version_, gen_.sample().gait.feet);
  const WalkChannel::Got got = channel_->Poll(live_version_, &live_steps_, gen_.sample().t);
  if (got != WalkChannel::Got::kNothing) TakeLive(got == WalkChannel::Got::kStop);
}

void WalkController::TakeLive(bool stop) noexcept {
  if (stop) {
    Stop();
  } else {
    // what was planned after the step under way gives way; the commands given at the start
    // are dropped, and the live steps, planned in the plan frame, are not remapped
    next_command_ = static_cast<int>(chunks_plan_.size());
    chunk_ = -1;
    gen_.Replace(live_steps_);
    walk_stats_.stopped = false;
    ++walk_stats_.commands_done;
  }
  walk_stats_.steps_planned = gen_.gait().step_count();
  ++live_version_;
}

// --live-replay: each recorded command at the first cycle at or after its time, planned here
// from the stance after the step under way as the channel planned it (this allocates: a replay
// is a lock-step run's, never a real-time one's)
void WalkController::ReplayCycle() noexcept {
  const double t = gen_.sample().t;
  while (replay_next_ < replay_.size() && t >= replay_[replay_next_].t - 1e-7) {
    replay_taken_.emplace_back(t, replay_next_);  // reserved: no allocation
    const Replayed& r = replay_[replay_next_++];
    if (r.text == "stop") {
      TakeLive(true);
      continue;
    }
    const walking::Gait& gait = gen_.gait();
    std::string note, error;
    if (WalkChannel::PlanText(r.text, gait.FeetAfter(gait.StartedBy(t)), replay_planning_, &live_steps_, &note,
                              &error)) {
      TakeLive(false);
    } else {
      notes_.push_back("--live-replay: at t = " + std::to_string(r.t) + " s: " + error);
    }
  }
}

// the commands as the cycles took them; a replay's: each replayed line at the cycle that took it
// (the same file as the record played, when every line was taken at its recorded cycle)
void WalkController::WriteLiveRecord() {
  if (walk_options_.live_record.empty() || (!channel_ && replay_.empty())) return;
  std::string text;
  char t[32];
  if (channel_) {
    for (const WalkChannel::Applied& a : channel_->applied_log()) {
      std::snprintf(t, sizeof t, "%.6f ", a.t);
      text += t + std::string(a.text) + "\n";
    }
  }
  for (const auto& [at, which] : replay_taken_) {
    std::snprintf(t, sizeof t, "%.6f ", at);
    text += t + replay_[which].text + "\n";
  }
  std::string error;
  if (!model::WriteWholeFile(walk_options_.live_record, text, &error)) notes_.push_back("--live-record: " + error);
  if (!channel_) return;
  // the record's room is reserved at open (the cycle never allocates): past it, said here
  const size_t taken = static_cast<size_t>(channel_->applied());
  if (taken > channel_->applied_log().size())
    notes_.push_back("--live-record: " + walk_options_.live_record + " holds the first " +
                     std::to_string(channel_->applied_log().size()) + " of the " +
                     std::to_string(taken) + " live commands taken (its room, kAppliedLog): a "
                     "replay of it stops there");
}

}  // namespace ohrp::controllers
