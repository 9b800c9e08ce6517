// Live walk commands (issue 30 item 5): lines on stdin (`walk --listen`) or on a local socket
// (`walk --socket PATH`, one client at a time, one reply line per command), each a walk command
// as for --command (goal, velocity, steps, random) or `stop`; `velocity VX VY WZ_DEG` without a
// duration walks until the next command or `stop`; `goal_now X Y YAW_DEG` is a goal in the frame
// of the feet's middle as they are now (the viewer's click on the floor; `goal` is in the frame of
// the stance after the step under way), refused farther than kLiveGoalRange. A command replaces
// what is planned after the step under way.
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

// a `goal_now` farther than this from the feet's middle is refused [m]
constexpr double kLiveGoalRange = 5.0;

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

  // the control cycle: where a new command starts and that stance's version, and the feet now
  // (no blocking, no allocation: skipped when the channel holds the lock)
  void Publish(const walking::FeetPose& feet, uint64_t version, const walking::FeetPose& now) noexcept;
  void Publish(const walking::FeetPose& feet, uint64_t version) noexcept { Publish(feet, version, feet); }
  enum class Got { kNothing, kSteps, kStop };
  // the control cycle: a plan made from `version` swapped into `*steps` (its capacity goes back
  // to the channel), or a stop; a plan made from another version is dropped and made again
  // `t`: the cycle's time, kept with each command taken (applied_log)
  Got Poll(uint64_t version, std::vector<walking::Footstep>* steps, double t = 0) noexcept;

  // each command the cycle took, at the cycle's time: the line as planned (a goal_now as its
  // goal_at, a velocity with its duration) or "stop"; at most kAppliedLog (walk --live-record)
  struct Applied {
    double t;
    char text[200];
  };
  static constexpr size_t kAppliedLog = 4096;
  const std::vector<Applied>& applied_log() const { return applied_log_; }

  // a line as planned on the channel (goal_at, or any --command) from the stance `feet` into
  // `*steps`; false with `*error` (walk --live-replay plans the recorded lines with it)
  static bool PlanText(const std::string& text, const walking::FeetPose& feet, const LivePlanning& planning,
                       std::vector<walking::Footstep>* steps, std::string* note, std::string* error);

  // counts, for the report
  int received() const { return received_; }
  int refused() const { return refused_; }
  int applied() const { return applied_; }


 private:
  // one line from a client (fd: where the reply goes, -1: none)
  void Line(const std::string& line, int reply_fd);
  // plans the pending command from the published stance, if any is pending
  void Plan();
  // `goal_now X Y YAW_DEG` checked (range), and with `now` as `goal_at` in the plan frame (from
  // the feet now); false with *error
  static bool GoalNow(const std::string& line, const walking::FeetPose* now, std::string* goal_at,
                      std::string* error);
  // `goal_at X Y YAW_DEG` (plan frame) as `goal` from the stance `feet`
  static std::string GoalFrom(const std::string& goal_at, const walking::FeetPose& feet);

  LivePlanning planning_;
  LineServer server_;

  std::mutex mutex_;  // guards everything below
  walking::FeetPose stance_{};
  uint64_t stance_version_ = 0;
  walking::FeetPose now_{};        // the feet now (for goal_now)
  bool have_stance_ = false;
  std::string pending_;            // the command line to plan ("" none)
  std::string pending_said_;       // as the client sent it (goal_now for goal_at)
  int pending_reply_ = -1;
  bool pending_stop_ = false;
  std::vector<walking::Footstep> planned_;
  uint64_t planned_version_ = 0;
  bool have_plan_ = false;
  bool replan_ = false;            // the last plan was dropped as stale: made again
  std::string last_planned_;       // the command line of the last plan
  std::vector<Applied> applied_log_;  // reserved at Open: the cycle never allocates
  std::atomic<int> received_{0}, refused_{0}, applied_{0};
};

}  // namespace ohrp::controllers
