// Programs started from an argument vector, never through a shell (see run_command.h).
#include "tool_process/run_command.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>

namespace ohrp::tool {
namespace {

// Forks and executes `argv` with stdin from `in_fd` (or /dev/null when -1) and stdout, stderr
// appended to `output` (or inherited). An exec that fails is reported through a close-on-exec
// pipe, so the caller learns "no such program" instead of an exit code 127. Returns the pid or
// -1 with `*error`.
pid_t Launch(const std::vector<std::string>& argv, const std::string& output, int in_fd,
             int close_in_child, std::string* error) {
  if (argv.empty()) {
    *error = "no program to run";
    return -1;
  }
  int out_fd = -1;
  if (!output.empty()) {
    out_fd = ::open(output.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (out_fd < 0) {
      *error = "cannot open '" + output + "': " + std::strerror(errno);
      return -1;
    }
  }
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) {
    if (out_fd >= 0) ::close(out_fd);
    *error = std::string("pipe: ") + std::strerror(errno);
    return -1;
  }
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (close_in_child >= 0) ::close(close_in_child);
    const int stdin_fd = in_fd >= 0 ? in_fd : ::open("/dev/null", O_RDONLY);
    if (stdin_fd >= 0) ::dup2(stdin_fd, 0);
    if (out_fd >= 0) {
      ::dup2(out_fd, 1);
      ::dup2(out_fd, 2);
    }
    ::execvp(args[0], args.data());
    const int e = errno;
    ssize_t ignored = ::write(report[1], &e, sizeof e);
    (void)ignored;
    ::_exit(127);
  }
  ::close(report[1]);
  if (out_fd >= 0) ::close(out_fd);
  if (pid < 0) {
    ::close(report[0]);
    *error = std::string("fork: ") + std::strerror(errno);
    return -1;
  }
  int e = 0;
  ssize_t n;
  do n = ::read(report[0], &e, sizeof e);
  while (n < 0 && errno == EINTR);
  ::close(report[0]);
  if (n == static_cast<ssize_t>(sizeof e)) {
    ::waitpid(pid, nullptr, 0);
    *error = "cannot run '" + argv[0] + "': " + std::strerror(e);
    return -1;
  }
  return pid;
}

int WaitFor(pid_t pid) {
  int st = 0;
  while (::waitpid(pid, &st, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

}  // namespace

int RunCommand(const std::vector<std::string>& argv, const std::string& output, std::string* error) {
  const pid_t pid = Launch(argv, output, -1, -1, error);
  return pid < 0 ? -1 : WaitFor(pid);
}

std::unique_ptr<PipeTo> PipeTo::Start(const std::vector<std::string>& argv,
                                      const std::string& output, std::string* error) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    *error = std::string("pipe: ") + std::strerror(errno);
    return nullptr;
  }
  // the child reads fds[0] as its stdin (dup2 clears close-on-exec) and closes our end
  const pid_t pid = Launch(argv, output, fds[0], fds[1], error);
  ::close(fds[0]);
  if (pid < 0) {
    ::close(fds[1]);
    return nullptr;
  }
  std::unique_ptr<PipeTo> p(new PipeTo());
  p->pid_ = pid;
  p->in_ = ::fdopen(fds[1], "w");
  return p;
}

int PipeTo::Close() {
  if (in_) std::fclose(in_);
  in_ = nullptr;
  const int code = pid_ > 0 ? WaitFor(pid_) : -1;
  pid_ = -1;
  return code;
}

PipeTo::~PipeTo() {
  if (pid_ > 0 || in_) Close();
}

}  // namespace ohrp::tool
