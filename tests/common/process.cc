// Child processes for the tests (see process.h).
#include "process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>

#include "shm_bridge/clock.h"  // MonotonicSeconds

namespace ohrp::testing {
namespace {

constexpr useconds_t kPollUs = 1000;  // [us] between two looks at a child that still runs

// the exit code of a waitpid status: the child's code, or 128 + the signal that ended it
int ExitCode(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -2;
}

// Looks at child `pid` until it ends or `timeout` [s] has passed: its exit code, -1 when it
// still runs, -3 when it is no child left to wait for.
int Await(pid_t pid, double timeout) {
  if (pid <= 0) return -3;  // waitpid would wait for any child
  int status = 0;
  if (std::isinf(timeout)) {
    pid_t r;
    while ((r = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
    }
    return r == pid ? ExitCode(status) : -3;
  }
  const double deadline = MonotonicSeconds() + timeout;
  for (;;) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) return ExitCode(status);
    if (r < 0) return -3;
    if (MonotonicSeconds() >= deadline) return -1;
    usleep(kPollUs);
  }
}

// in the child: `fd` (stdout or stderr) written to the file `path` instead
void Redirect(const std::string& path, bool append, int fd) {
  const int file = open(path.c_str(), O_WRONLY | O_CREAT | (append ? O_APPEND : O_TRUNC), 0644);
  if (file < 0) return;  // the stream stays the test's
  dup2(file, fd);
  if (file != fd) close(file);
}

}  // namespace

pid_t Spawn(const std::vector<std::string>& argv, const Output& output) {
  // the argument vector is made before the fork: the child only redirects and execs
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid != 0) return pid;
  if (!output.out.empty()) Redirect(output.out, output.append, STDOUT_FILENO);
  if (!output.err.empty()) {
    if (output.err == output.out) {
      dup2(STDOUT_FILENO, STDERR_FILENO);  // one file, one offset
    } else {
      Redirect(output.err, output.append, STDERR_FILENO);
    }
  }
  execvp(args[0], args.data());
  _exit(127);
}

pid_t Spawn(const std::function<int()>& body) {
  const pid_t pid = fork();
  if (pid == 0) {
    int code = 99;
    try {
      code = body();
    } catch (...) {
    }
    _exit(code);
  }
  return pid;
}

int WaitExit(pid_t pid, double timeout) {
  const int code = Await(pid, timeout);
  if (code == -1) Kill(pid);
  return code;
}

int WaitExit(pid_t* pid, double timeout) {
  if (*pid <= 0) return -1;
  const int code = Await(*pid, timeout);
  if (code >= 0) *pid = -1;
  return code;
}

bool Running(pid_t pid) {
  if (pid <= 0) return false;  // waitid would look at no child, or at all
  siginfo_t info{};
  if (waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0) return false;
  return info.si_pid == 0;  // no state change to report: still running
}

void Kill(pid_t pid) {
  if (pid <= 0) return;
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
}

void Kill(pid_t* pid) {
  Kill(*pid);
  *pid = -1;
}

int Terminate(pid_t pid, double timeout) {
  if (pid <= 0) return -3;
  kill(pid, SIGCONT);
  kill(pid, SIGTERM);
  return WaitExit(pid, timeout);
}

//---------------- pipe ----------------

Pipe::Pipe() {
  if (pipe(fds_) != 0) fds_[0] = fds_[1] = -1;
}

Pipe::~Pipe() {
  for (int fd : fds_) {
    if (fd >= 0) close(fd);
  }
}

bool Pipe::Send(char c) { return fds_[1] >= 0 && ::write(fds_[1], &c, 1) == 1; }

void Pipe::CloseSendEnd() {
  if (fds_[1] >= 0) close(fds_[1]);
  fds_[1] = -1;
}

bool Pipe::Receive(double timeout) {
  pollfd p{fds_[0], POLLIN, 0};
  const int ms = std::isinf(timeout) ? -1 : static_cast<int>(timeout * 1000);
  if (poll(&p, 1, ms) != 1) return false;
  char c = 0;
  return ::read(fds_[0], &c, 1) == 1;
}

}  // namespace ohrp::testing
