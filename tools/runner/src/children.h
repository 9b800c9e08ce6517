// The runner's child processes (sim_host, the controllers): started with their output in a
// file, echoed with a prefix while they run, reaped, stopped.
#pragma once

#include <sys/types.h>

#include <fstream>
#include <string>
#include <vector>

namespace ohrp::runner {

// a child process whose output goes to a file, echoed with a prefix while it runs
struct Child {
  std::string label;
  std::vector<std::string> argv;
  std::string output;  // file receiving stdout and stderr
  pid_t pid = -1;
  bool done = false;
  int exit_code = -1;  // 128 + signal when killed
  std::streamoff echoed = 0;
};

// starts `c` (its argv[0] a path) in `cwd`, its output into c->output; false with a reason
bool Spawn(Child* c, const std::string& cwd, std::string* error);
// notes whether `c` has ended (and its exit code), without waiting
void Reap(Child* c);
// prints the complete lines `c` wrote since the last call, prefixed by its label, when `echo`
void Echo(Child* c, bool echo);
// sends `sig` to `c` while it runs
void Stop(Child* c, int sig);
// waits until every child in `cs` is done or `deadline` (MonotonicSeconds) passes
void WaitAll(std::vector<Child*> cs, double deadline, bool echo);
// "walk: exit 3, ..." when every controller has ended with a refusal (exit 2: its command line,
// 3: a file or the robot it attached to), "" otherwise
std::string EveryControllerRefused(const std::vector<Child>& ctl);

}  // namespace ohrp::runner
