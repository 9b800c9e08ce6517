// Child processes for the tests, in one place: a program started with its output in files, a
// function run in a forked child, the wait for a child's end with a timeout (its exit code, or
// 128 + the signal that ended it), ending a child, and a pipe that orders steps between a test
// and its children.
//
// Children are identified by pid. A function that takes `pid_t*` treats the variable as the
// test's record of a child it still has to end: once the child is reaped the variable is set to
// -1, so that a fixture's TearDown (Kill) leaves it alone. A function that takes a `pid_t` leaves
// nothing behind: a child still running at its timeout is killed and reaped.
#pragma once

#include <signal.h>  // kill() and the signals, for the tests that signal their children
#include <sys/types.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace ohrp::testing {

// a timeout that never expires [s]
inline constexpr double kNoTimeout = std::numeric_limits<double>::infinity();

// Where a spawned program writes. Each stream is the test's own ("") or a file, created (0644)
// or truncated, or appended to with `append`. The same path for both opens the file once: the
// two streams share one offset and interleave in the order written. "/dev/null" discards.
struct Output {
  std::string out = {};  // stdout's file; "" the test's stdout
  std::string err = {};  // stderr's file; "" the test's stderr
  bool append = false;   // append to the files instead of truncating them
};

// stdout and stderr both into the file `path` (truncated, or appended to)
inline Output ToFile(const std::string& path, bool append = false) { return {path, path, append}; }

// Starts the program `argv[0]` (a path, or a name looked up in PATH) with the arguments
// `argv[1..]` in a child process writing where `output` says. Returns the child's pid; a program
// that cannot be started makes the child exit 127.
pid_t Spawn(const std::vector<std::string>& argv, const Output& output = {});

// Runs `body` in a forked child that exits with its return value (99 when it throws); the child
// never returns into the test framework. `body` may also end the child itself with _exit().
pid_t Spawn(const std::function<int()>& body);

// Waits up to `timeout` [s] for child `pid` to end. Returns its exit code, 128 + the signal when
// a signal ended it, -1 on timeout (the child is then killed with SIGKILL and reaped), -3 when
// `pid` is no child of this process left to wait for. kNoTimeout waits as long as it takes.
int WaitExit(pid_t pid, double timeout = 5.0);

// Waits up to `timeout` [s] for child `*pid` to end. Returns its exit code (128 + a signal) and
// sets `*pid` to -1; returns -1 when it still runs at the timeout (it is left running, `*pid`
// kept) or when `*pid` <= 0; -3 when `*pid` is no child left to wait for. A timeout of 0 looks
// once, without waiting.
int WaitExit(pid_t* pid, double timeout);

// One look at child `pid`: true while it runs. It is not reaped: once ended, it stays to be
// waited for (WaitExit) or killed (Kill). False when `pid` is no child of this process.
bool Running(pid_t pid);

// Ends child `pid` now: SIGKILL, then reaped. Nothing when `pid` <= 0.
void Kill(pid_t pid);
// Kill(*pid), then `*pid` = -1.
void Kill(pid_t* pid);

// Asks child `pid` to end: SIGCONT (a stopped child would not act on the next) and SIGTERM, then
// WaitExit(pid, timeout) (killed when it has not ended by then). Returns WaitExit's answer.
int Terminate(pid_t pid, double timeout = 5.0);

// A pipe that orders steps between a test and the children it forks: one byte is one signal.
// Both ends stay open in both processes.
class Pipe {
 public:
  Pipe();
  ~Pipe();
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;

  // Writes one byte; false when it could not.
  bool Send(char c = 'x');
  // True when a byte arrived within `timeout` [s] (kNoTimeout: waits as long as it takes);
  // false at once when every send end is closed (see CloseSendEnd).
  bool Receive(double timeout = 5.0);
  // Closes this process's send end: call it in the parent once the child that sends has been
  // spawned, so that the child's exit (its send end closing) ends a Receive instead of leaving
  // it waiting for a byte that cannot come.
  void CloseSendEnd();

 private:
  int fds_[2] = {-1, -1};
};

}  // namespace ohrp::testing
