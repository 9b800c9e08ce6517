// Real-time set-up of the calling thread (hw_driver's loop, a controller with --rt-priority,
// bench_rt): SCHED_FIFO, locked memory, a pre-faulted stack and
// the smallest timer slack, where the system permits; what could not be done is reported as one warning line each.
#pragma once

#include <string>
#include <vector>

namespace ohrp::rt {

struct RtSettings {
  int priority = 80;           // SCHED_FIFO priority of the calling thread; 0: leave the policy
  bool lock_memory = true;     // mlockall(MCL_CURRENT | MCL_FUTURE)
  int stack_prefault_kb = 256; // stack touched once so the loop takes no page fault on it
  // the calling thread's timer slack [ns] (prctl PR_SET_TIMERSLACK; Linux's default is 50 us,
  // by which a SCHED_OTHER thread's timed sleeps may end late); 0: leave it
  long timer_slack_ns = 1;
};

struct RtReport {
  bool fifo = false;           // the calling thread runs SCHED_FIFO at `priority`
  int priority = 0;
  bool memory_locked = false;
  long timer_slack_ns = -1;    // the thread's timer slack after the set-up [ns]; -1: unknown
  std::vector<std::string> warnings;  // one line each, e.g. "SCHED_FIFO refused (...)"
  std::string Describe() const;       // e.g. "SCHED_FIFO 80, memory locked"
};

// Applies `settings` to the calling thread and process. Never fails: what the system refuses
// is listed in the report's warnings and the loop runs without it.
RtReport SetUpRealTime(const RtSettings& settings);

}  // namespace ohrp::rt
