// The controller runner: attach to a robot segment by name, drive a Controller through its
// lifecycle (controller.h) in a read -> update -> write loop, and turn the way the run ended
// into a message and an exit code.
//
//   attach     RobotAdaptor::open(segment). kNoSegment / kProducerNotReady are retried every
//              50 ms until `attach_timeout` [s] has passed (0: fail at once); any other
//              failure ends the run at once with the adaptor's message.
//   configure  the controller checks its files against the header (joint names and count).
//   loop       read -> (activate on the first block) -> update -> self-collision check
//              (self_collision_guard.h: may hold the last safe references) -> write, until read/write
//              report an end (the producer stopped, failed or is gone, no sensors within the
//              read timeout, or the producer dropped this controller for missing its own
//              timeout: shm_bridge/controller_loss.h) or SIGINT/SIGTERM arrives. No allocation, throwing or logging
//              in the loop; problems are counted and printed after it.
//              Every sensor block also goes to the fall watch (fall_watch.h, limits from the
//              controller: Controller::fall_limits): a fall ends the loop at once (the
//              producer holds the last commands) with kExitFell, its time, cycle and cause.
//   end        deactivate, close the adaptor (the controller slot is freed), close; then the
//              controller's own verdict (Controller::failure): a run it cannot verify as done
//              (e.g. walk's steps not landed) is kExitFailed. No success is printed after a fall
//              or a failure.
//
// Exit codes (ExitCode): see below; programs list them in their --help.
#pragma once

#include <iosfwd>
#include <string>

#include "controllers/controller.h"

namespace ohrp::controllers {

enum ExitCode : int {
  kExitOk = 0,              // the producer ended its run normally, or SIGINT/SIGTERM
  kExitUsage = 2,           // bad command line
  kExitConfig = 3,          // a file is malformed or does not fit the robot
  kExitAttach = 4,          // could not attach (no segment, layout mismatch, slot taken...)
  kExitProducerLost = 5,    // the producer's process is gone, or no sensors within the timeout
  kExitProducerFailed = 6,  // the producer ended reporting a failure (e.g. diverged)
  kExitDropped = 7,         // the producer dropped this controller: it did not answer within
                            // the producer's timeout (e.g. stopped by SIGSTOP, then resumed)
  kExitFell = 8,            // the robot fell (the fall watch, fall_watch.h: when and why)
  kExitFailed = 9,          // the controller could not do what it was asked, by its own
                            // measurements (e.g. walk: steps that did not land)
};

// One paragraph for --help footers.
const char* ExitCodeHelp();

struct RunOptions {
  std::string program = "controller";  // name used at the start of every message
  std::string segment;                 // segment name (see shm::SegmentObjectName)
  double attach_timeout = 0.0;         // [s] keep retrying a missing segment this long
  double read_timeout = 2.0;           // [s] longest wait for one sensor block
  double retry_interval = 0.05;        // [s] between attach attempts
  // the online self-collision check (controllers/self_collision_guard.h): its file, empty for
  // none. When `self_collision_is_default` and the file is for another robot (model hash), the
  // check is off with a note; otherwise a file that does not fit is exit 3.
  std::string self_collision;
  bool self_collision_is_default = false;
  bool fall_watch = true;              // false: falls are not detected (--no-fall-watch)
  int rt_priority = 0;                 // > 0: the cycle loop runs SCHED_FIFO at this priority
                                       // with locked memory, where permitted (--rt-priority)
};

// The self-collision file shipped for HRP-1S (mjcf/hrp1s/selfcollision.yaml of the data folder,
// cli/data_dir.h).
std::string DefaultSelfCollisionFile();

// What happened, for tests and callers that want more than the exit code.
struct RunReport {
  ExitCode exit_code = kExitOk;
  uint64_t cycles = 0;       // command blocks written
  double first_time = 0.0;   // producer time of the first sensor block [s]
  double last_time = 0.0;    // producer time of the last sensor block [s]
  FallEvent fall;            // the fall the watch saw (cause kNone: none)
  std::string failure;       // the controller's own verdict when it failed
};

// Installs SIGINT/SIGTERM handlers that ask a running RunController to stop (without
// SA_RESTART, so blocking waits return early). Programs call it once in main.
void InstallStopSignalHandlers();
// Asks RunController to stop after the current cycle (async-signal-safe).
void RequestStop() noexcept;
// Clears a pending stop request (for tests that run several controllers in one process).
void ClearStopRequest() noexcept;

// Runs `controller` (kUnconfigured) against segment `options.segment` until the run ends.
// Messages go to `out` (the start line and the summary) and `err` (why a run failed).
// Returns the exit code; fills `*report` when not null.
int RunController(Controller& controller, const RunOptions& options, std::ostream& out,
                  std::ostream& err, RunReport* report = nullptr);

}  // namespace ohrp::controllers
