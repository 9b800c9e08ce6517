// Live walk commands: the channel's thread reads and plans, the control cycle takes the plans
// without waiting (see walk_channel.h).
#include "controllers/walk_channel.h"

#include <cstdio>
#include <sstream>

#include "controllers/walk.h"

namespace ohrp::controllers {

bool WalkChannel::Open(int fd, const std::string& socket_path, const LivePlanning& planning,
                       std::string* error) {
  Close();
  planning_ = planning;
  return server_.Open(
      fd, socket_path, "walk", [this](const std::string& line, int reply) { Line(line, reply); },
      [this] { Plan(); }, error);
}

void WalkChannel::Close() { server_.Close(); }

//---------------- the control cycle's side ----------------

void WalkChannel::Publish(const walking::FeetPose& feet, uint64_t version) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  stance_ = feet;
  stance_version_ = version;
  have_stance_ = true;
}

WalkChannel::Got WalkChannel::Poll(uint64_t version, std::vector<walking::Footstep>* steps) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return Got::kNothing;
  if (pending_stop_) {
    pending_stop_ = false;
    have_plan_ = false;
    ++applied_;
    return Got::kStop;
  }
  if (!have_plan_) return Got::kNothing;
  have_plan_ = false;
  if (planned_version_ != version) {  // made from a stance that has moved on: again
    replan_ = true;
    return Got::kNothing;
  }
  steps->swap(planned_);
  ++applied_;
  return Got::kSteps;
}

//---------------- the channel's thread ----------------

void WalkChannel::Line(const std::string& line, int reply) {
  // a velocity without a duration walks until the next command
  std::istringstream words(line);
  std::string verb, w;
  int count = 0;
  words >> verb;
  while (words >> w) ++count;
  char until[32];
  std::snprintf(until, sizeof until, " %g", planning_.until_stop);
  const std::string text = verb == "velocity" && count == 3 ? line + until : line;
  WalkCommand c;
  std::string error;
  const bool stop = line == "stop";
  const bool ok = stop || (ParseWalkCommand(text, &c, &error) && c.kind != WalkCommand::Kind::kWait);
  if (!ok && error.empty())
    error = "\"" + line + "\": wait is not a live command (send the next one when it is due)";
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++received_;
    if (stop) {
      pending_stop_ = true;
      pending_.clear();
      have_plan_ = false;
    } else if (ok) {
      pending_ = text;
      pending_reply_ = reply;
    } else {
      ++refused_;
    }
  }
  if (stop) server_.Reply(reply, "ok: stop");
  if (!ok) server_.Reply(reply, "error: " + error);
}

void WalkChannel::Plan() {
  std::string text;
  int reply = -1;
  bool again = false;
  walking::FeetPose feet;
  uint64_t version = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!have_stance_) return;
    again = pending_.empty() && replan_ && !last_planned_.empty();
    if (pending_.empty() && !again) return;
    text = again ? last_planned_ : pending_;
    reply = again ? -1 : pending_reply_;
    pending_.clear();
    replan_ = false;
    feet = stance_;
    version = stance_version_;
  }
  WalkCommand c;
  std::string note, error;
  std::vector<walking::Footstep> steps;
  bool ok = ParseWalkCommand(text, &c, &error) &&
            PlanWalkCommand(c, feet, planning_.limits, planning_.step_time, &steps, &note, &error);
  const size_t count = steps.size();
  if (ok && count > planning_.max_steps) {
    error = "\"" + text + "\": " + std::to_string(count) + " steps, more than " +
            std::to_string(planning_.max_steps) + " at once";
    ok = false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!ok) {
      ++refused_;
    } else if (pending_.empty() && !pending_stop_) {  // else a newer command came meanwhile
      planned_.swap(steps);
      planned_version_ = version;
      have_plan_ = true;
      last_planned_ = text;
    }
  }
  if (!ok) server_.Reply(reply, "error: " + error);
  else if (!again)
    server_.Reply(reply, "ok: \"" + text + "\": " + std::to_string(count) +
                     " steps planned" + (note.empty() ? "" : "; " + note));
}

}  // namespace ohrp::controllers
