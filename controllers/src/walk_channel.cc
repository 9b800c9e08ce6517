// Live walk commands: the channel's thread reads and plans, the control cycle takes the plans
// without waiting (see walk_channel.h).
#include "controllers/walk_channel.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "controllers/walk.h"

namespace ohrp::controllers {

bool WalkChannel::Open(int fd, const std::string& socket_path, const LivePlanning& planning,
                       std::string* error) {
  Close();
  planning_ = planning;
  applied_log_.reserve(kAppliedLog);
  return server_.Open(
      fd, socket_path, "walk", [this](const std::string& line, int reply) { Line(line, reply); },
      [this] { Plan(); }, error);
}

void WalkChannel::Close() { server_.Close(); }

//---------------- the control cycle's side ----------------

void WalkChannel::Publish(const walking::FeetPose& feet, uint64_t version,
                          const walking::FeetPose& now) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  stance_ = feet;
  now_ = now;
  stance_version_ = version;
  have_stance_ = true;
}

WalkChannel::Got WalkChannel::Poll(uint64_t version, std::vector<walking::Footstep>* steps,
                                   double t) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return Got::kNothing;
  const auto log = [&](const std::string& text) {
    if (applied_log_.size() >= kAppliedLog) return;
    Applied a{t, {}};
    std::snprintf(a.text, sizeof a.text, "%s", text.c_str());
    applied_log_.push_back(a);  // within the capacity reserved at Open
  };
  if (pending_stop_) {
    pending_stop_ = false;
    have_plan_ = false;
    ++applied_;
    log("stop");
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
  log(last_planned_);
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
  std::string text = verb == "velocity" && count == 3 ? line + until : line;
  WalkCommand c;
  std::string error;
  const bool stop = line == "stop";
  const bool ok = stop || (verb == "goal_now" ? GoalNow(line, nullptr, nullptr, &error)
                                              : verb != "goal_at" && ParseWalkCommand(text, &c, &error) &&
                                                    c.kind != WalkCommand::Kind::kWait);
  if (!ok && error.empty() && verb == "goal_at")
    error = "\"" + line + "\": goal_at is the walk's own form (send goal_now or goal)";
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
      pending_said_ = verb == "goal_now" ? line : text;
      pending_reply_ = reply;
    } else {
      ++refused_;
    }
  }
  if (stop) server_.Reply(reply, "ok: stop");
  if (!ok) server_.Reply(reply, "error: " + error);
}

void WalkChannel::Plan() {
  std::string text, said;
  int reply = -1;
  bool again = false;
  walking::FeetPose feet, now;
  uint64_t version = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!have_stance_) return;
    again = pending_.empty() && replan_ && !last_planned_.empty();
    if (pending_.empty() && !again) return;
    text = again ? last_planned_ : pending_;
    said = again ? last_planned_ : pending_said_;
    reply = again ? -1 : pending_reply_;
    pending_.clear();
    replan_ = false;
    feet = stance_;
    now = now_;
    version = stance_version_;
  }
  std::string note, error;
  std::vector<walking::Footstep> steps;
  // a goal from the feet now: in the plan frame, so that a re-plan keeps the same goal
  if (text.rfind("goal_now ", 0) == 0) GoalNow(text, &now, &text, &error);
  const bool ok = PlanText(text, feet, planning_, &steps, &note, &error);
  const size_t count = steps.size();
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
  if (!ok) server_.Reply(reply, "error: " + (said == text ? error : "\"" + said + "\" as " + error));
  else if (!again)
    server_.Reply(reply, "ok: \"" + said + "\": " + std::to_string(count) +
                     " steps planned" + (note.empty() ? "" : "; " + note));
}

bool WalkChannel::PlanText(const std::string& text, const walking::FeetPose& feet,
                           const LivePlanning& planning, std::vector<walking::Footstep>* steps,
                           std::string* note, std::string* error) {
  const std::string command = text.rfind("goal_at ", 0) == 0 ? GoalFrom(text, feet) : text;
  WalkCommand c;
  if (!ParseWalkCommand(command, &c, error) ||
      !PlanWalkCommand(c, feet, planning.limits, planning.step_time, steps, note, error))
    return false;
  if (steps->size() > planning.max_steps) {
    *error = "\"" + command + "\": " + std::to_string(steps->size()) + " steps, more than " +
             std::to_string(planning.max_steps) + " at once";
    return false;
  }
  return true;
}

//---------------- goals from the feet now (the viewer's click) ----------------

bool WalkChannel::GoalNow(const std::string& line, const walking::FeetPose* now, std::string* goal_at,
                          std::string* error) {
  std::istringstream in(line);
  std::string verb, extra;
  double x, y, yaw_deg;
  if (!(in >> verb >> x >> y >> yaw_deg) || (in >> extra) || !std::isfinite(x) || !std::isfinite(y) ||
      !std::isfinite(yaw_deg)) {
    *error = "\"" + line + "\": goal_now takes X Y YAW_DEG (three numbers, e.g. goal_now 1.0 0 90)";
    return false;
  }
  const double range = std::hypot(x, y);
  if (range > kLiveGoalRange) {
    char why[160];
    std::snprintf(why, sizeof why, "%.2f m from the feet, farther than the %.0f m a live goal may be "
                  "(choose a nearer point)", range, kLiveGoalRange);
    *error = "\"" + line + "\": " + why;
    return false;
  }
  if (!now) return true;  // checked only
  const walking::Frame2 m = walking::MidFrame(*now);
  const double c = std::cos(m.yaw), s = std::sin(m.yaw);
  char text[128];
  std::snprintf(text, sizeof text, "goal_at %.6f %.6f %.6f", m.p.x() + c * x - s * y, m.p.y() + s * x + c * y,
                (m.yaw * 180 / M_PI) + yaw_deg);
  *goal_at = text;
  return true;
}

std::string WalkChannel::GoalFrom(const std::string& goal_at, const walking::FeetPose& feet) {
  std::istringstream in(goal_at);
  std::string verb;
  double x = 0, y = 0, yaw_deg = 0;
  in >> verb >> x >> y >> yaw_deg;
  const walking::Frame2 m = walking::MidFrame(feet);
  const double c = std::cos(m.yaw), s = std::sin(m.yaw), dx = x - m.p.x(), dy = y - m.p.y();
  double yaw = yaw_deg * M_PI / 180 - m.yaw;
  yaw = std::atan2(std::sin(yaw), std::cos(yaw));
  char text[128];
  std::snprintf(text, sizeof text, "goal %.6f %.6f %.6f", c * dx + s * dy, -s * dx + c * dy, yaw * 180 / M_PI);
  return text;
}

}  // namespace ohrp::controllers
