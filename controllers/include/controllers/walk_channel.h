// Live walk commands (issue 30 item 5): lines on stdin (`walk --listen`) or on a local socket
// (`walk --socket PATH`, one client at a time, one reply line per command), each a walk command
// as for --command (goal, velocity, steps, random) or `stop`; `velocity VX VY WZ_DEG` without a
// duration walks until the next command or `stop`. A command replaces what is planned after the
// step under way.
//
// Planning allocates, so it runs on the channel's own thread, from the stance the control cycle
// publishes (the feet after the step under way, with a version that changes whenever that stance
// does). The cycle takes a plan only if it was made from its current version, by swapping
// vectors (no allocation), and never waits: every call from the cycle is a try_lock.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "controllers/line_server.h"
#include "walking/footsteps.h"

namespace ohrp::controllers {

// what a walk command line becomes on the channel
struct LivePlanning {
  walking::StepLimits limits;
  double step_time = 0.8;        // [s]
  double until_stop = 600;       // [s] a velocity without a duration walks this long at most
  size_t max_steps = 10000;      // a plan of more steps is refused (the cycle's room for them)
};

class WalkChannel {
 public:
  WalkChannel() = default;
  ~WalkChannel() { Close(); }
  WalkChannel(const WalkChannel&) = delete;
  WalkChannel& operator=(const WalkChannel&) = delete;

  // starts reading lines from `fd` (-1: none; e.g. 0 for stdin) and from a local stream socket
  // at `socket_path` ("": none; an existing socket file there is replaced); false with `*error`
  // when the socket cannot be made
  bool Open(int fd, const std::string& socket_path, const LivePlanning& planning, std::string* error);
  void Close();
  bool open() const { return server_.open(); }

  // the control cycle: where a new command starts and that stance's version (no blocking, no
  // allocation: skipped when the channel holds the lock)
  void Publish(const walking::FeetPose& feet, uint64_t version) noexcept;
  enum class Got { kNothing, kSteps, kStop };
  // the control cycle: a plan made from `version` swapped into `*steps` (its capacity goes back
  // to the channel), or a stop; a plan made from another version is dropped and made again
  Got Poll(uint64_t version, std::vector<walking::Footstep>* steps) noexcept;

  // counts, for the report
  int received() const { return received_; }
  int refused() const { return refused_; }
  int applied() const { return applied_; }


 private:
  // one line from a client (fd: where the reply goes, -1: none)
  void Line(const std::string& line, int reply_fd);
  // plans the pending command from the published stance, if any is pending
  void Plan();

  LivePlanning planning_;
  LineServer server_;

  std::mutex mutex_;  // guards everything below
  walking::FeetPose stance_{};
  uint64_t stance_version_ = 0;
  bool have_stance_ = false;
  std::string pending_;            // the command line to plan ("" none)
  int pending_reply_ = -1;
  bool pending_stop_ = false;
  std::vector<walking::Footstep> planned_;
  uint64_t planned_version_ = 0;
  bool have_plan_ = false;
  bool replan_ = false;            // the last plan was dropped as stale: made again
  std::string last_planned_;       // the command line of the last plan
  std::atomic<int> received_{0}, refused_{0}, applied_{0};
};

}  // namespace ohrp::controllers
