// reach's live goals (issue 34 item 2; docs/planning.md "Live goals"): lines on stdin (`reach
// --listen`) or on a local socket (`reach --socket PATH`, one client at a time, one reply line
// per command), through the same transport as walk's (controllers/line_server.h):
//
//   joints NAME=VALUE,...                       the group's joints named (the others keep the
//                                               previous goal's values) [rad]
//   pose SITE,X,Y,Z[,ROLL,PITCH,YAW] [SITE,...] hand poses in the base frame [m, rad], one per
//                                               limb of the group
//
// Each goal is resolved on the channel's thread (the IK and the goal's collision check in the
// stance pose allocate, so they never run in the control cycle) by the owner's `resolve`, and
// replied "ok: goal N queued" or "error: why". The control cycle takes the resolved goals in
// order, without waiting or allocating (a try_lock; the values copied into preallocated room),
// and reaches each after the ones before it.
#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <vector>

#include "controllers/line_server.h"
#include "controllers/reach.h"

namespace ohrp::controllers {

class ReachChannel {
 public:
  // a goal's group values from `spec` (the previous goal's values in `*values` on entry);
  // false with `*error`
  using Resolve = std::function<bool(const GoalSpec& spec, std::vector<double>* values,
                                     std::string* error)>;

  ReachChannel() = default;
  ~ReachChannel() { Close(); }
  ReachChannel(const ReachChannel&) = delete;
  ReachChannel& operator=(const ReachChannel&) = delete;

  // starts the channel (LineServer::Open's `fd` and `socket_path`); `start`: the group's values
  // the first live goal starts from; at most `capacity` goals are taken in a run
  bool Open(int fd, const std::string& socket_path, const std::vector<double>& start,
            size_t capacity, Resolve resolve, std::string* error);
  void Close();
  bool open() const { return server_.open(); }

  // the control cycle: the next resolved goal copied into `*values` (the group's size) and its
  // false when none is waiting or the channel holds the lock
  bool Poll(std::vector<double>* values) noexcept;

  int received() const { return received_; }
  int refused() const { return refused_; }
  int taken() const { return taken_; }
  // the text of goal `k` (0-based, in the order taken) as the client sent it
  std::string text(size_t k) const;

 private:
  void Line(const std::string& line, int reply_fd);

  LineServer server_;
  Resolve resolve_;
  size_t capacity_ = 0;
  std::vector<double> last_;  // the last accepted goal's values (the channel's thread)
  mutable std::mutex mutex_;  // guards the queue and the texts
  std::vector<std::vector<double>> queue_;  // accepted, not yet taken (capacity_ preallocated)
  size_t head_ = 0, count_ = 0;
  std::vector<std::string> texts_;  // every accepted goal's line
  std::atomic<int> received_{0}, refused_{0}, taken_{0};
};

}  // namespace ohrp::controllers
