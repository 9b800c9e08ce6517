// sim_host's local control channel (--control-socket PATH): pause, resume, step, reset and push
// a running simulation from another process (ohrp view --control, a script). Lines come in on
// the channel's own thread (controllers/line_server.h), are parsed there, and are handed to the
// control loop through one preallocated slot; the loop applies them between control cycles
// (never inside the physics step), without allocating or logging, and marks them done; the
// channel's thread then answers the line and records the action in the run folder
// (actions.jsonl). Docs: docs/architecture.md "Control channel".
#pragma once

#include <mujoco/mujoco.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace ohrp::sim {

struct ControlAction {
  enum Kind { kNone, kPause, kResume, kStep, kReset, kPush, kStatus } kind = kNone;
  int steps = 1;         // step: control periods to run, then paused again
  int keyframe = -1;     // reset: the keyframe's index; -1 the run's start (--keyframe or qpos0)
  int body = -1;         // push: the body's id
  double force[3] = {0, 0, 0};  // push: world frame [N], at the body's centre of mass
  double duration = 0;   // push: [s] of simulated time (rounded up to whole control periods)
};

// what the loop did with an action (filled by the loop, read by the channel's thread)
struct ControlOutcome {
  double time = 0;       // simulated time when it was applied [s]
  uint64_t cycle = 0;    // control cycles done then
  bool paused = false;   // paused after it
  double push_end = 0;   // push: the simulated time it ends [s]
};

// Parses one line: "pause", "resume", "step [N]", "reset [KEYFRAME]", "push BODY FX FY FZ
// DURATION", "status". False with `*error` saying what would work (the verbs and their forms,
// the model's bodies or keyframes when a name is unknown).
bool ParseControlLine(const std::string& line, const mjModel* m, ControlAction* out,
                      std::string* error);

class ControlChannel {
 public:
  // listens at `socket_path` (a socket left there is replaced); records applied actions in
  // `actions_path` ("": not recorded); pushes on `base_body` are also written as the sim_host
  // --push that reproduces them
  static std::unique_ptr<ControlChannel> Open(const std::string& socket_path,
                                              const std::string& actions_path, const mjModel* m,
                                              int base_body, std::string* error);
  ~ControlChannel();

  //---- the control loop's side: allocation-free, never blocks
  // the action waiting in the slot, if any (then Done must follow)
  bool Take(ControlAction* out);
  void Done(const ControlOutcome& outcome);
  // the loop has ended: lines from now on are answered so
  void Close();

 private:
  ControlChannel() = default;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ohrp::sim
