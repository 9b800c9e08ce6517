// reach's live goals: the channel's thread parses and resolves, the control cycle takes them
// without waiting (controllers/reach_live.h).
#include "controllers/reach_live.h"

#include <sstream>

#include "controllers/reach_goals.h"

namespace ohrp::controllers {
namespace {

// the words after the verb, split at commas and spaces (a pose's hands are separate words)
std::vector<std::string> Items(std::istringstream& words) {
  std::vector<std::string> items;
  for (std::string w; words >> w;) {
    std::stringstream parts(w);
    for (std::string item; std::getline(parts, item, ',');)
      if (!item.empty()) items.push_back(item);
  }
  return items;
}

}  // namespace

bool ReachChannel::Open(int fd, const std::string& socket_path, const std::vector<double>& start,
                        size_t capacity, Resolve resolve, std::string* error) {
  Close();
  resolve_ = std::move(resolve);
  capacity_ = capacity;
  last_ = start;
  queue_.assign(capacity, std::vector<double>(start.size(), 0.0));
  head_ = count_ = 0;
  texts_.clear();
  texts_.reserve(capacity);
  return server_.Open(
      fd, socket_path, "reach", [this](const std::string& line, int reply) { Line(line, reply); },
      nullptr, error);
}

void ReachChannel::Close() { server_.Close(); }

bool ReachChannel::Poll(std::vector<double>* values) noexcept {
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock() || count_ == 0) return false;
  std::copy(queue_[head_].begin(), queue_[head_].end(), values->begin());
  head_ = (head_ + 1) % capacity_;
  --count_;
  ++taken_;
  return true;
}

std::string ReachChannel::text(size_t k) const {
  std::lock_guard<std::mutex> lock(mutex_);
  return k < texts_.size() ? texts_[k] : "";
}

void ReachChannel::Line(const std::string& line, int reply) {
  ++received_;
  auto refuse = [&](const std::string& why) {
    ++refused_;
    server_.Reply(reply, "error: " + why);
  };
  std::istringstream words(line);
  std::string verb;
  words >> verb;
  GoalSpec spec;
  std::string error;
  const std::vector<std::string> items = Items(words);
  if (verb == "joints") {
    if (!ParseJointsGoal(items, "joints", &spec.joints, &error)) return refuse(error);
    if (spec.joints.empty()) return refuse("joints: give NAME=VALUE,... [rad]");
  } else if (verb == "pose") {
    if (!ParseHandPoses(items, "pose", &spec.hands, &error)) return refuse(error);
    if (spec.hands.empty()) return refuse("pose: give SITE,X,Y,Z[,ROLL,PITCH,YAW] for each hand");
  } else {
    return refuse("\"" + line + "\": unknown command (joints NAME=VALUE,... | pose SITE,X,Y,Z[,R,P,Y] ...)");
  }
  std::vector<double> values = last_;
  if (!resolve_(spec, &values, &error)) return refuse(error);
  std::lock_guard<std::mutex> lock(mutex_);
  if (texts_.size() >= capacity_) {
    ++refused_;
    server_.Reply(reply, "error: " + std::to_string(capacity_) + " goals already taken in this run");
    return;
  }
  std::copy(values.begin(), values.end(), queue_[(head_ + count_) % capacity_].begin());
  ++count_;
  texts_.push_back(line);
  last_ = values;
  server_.Reply(reply, "ok: goal " + std::to_string(texts_.size()) + " queued");
}

}  // namespace ohrp::controllers
