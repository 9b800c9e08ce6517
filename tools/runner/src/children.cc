// The runner's child processes (children.h).
#include "children.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "shm_bridge/clock.h"

namespace ohrp::runner {

bool Spawn(Child* c, const std::string& cwd, std::string* error) {
  const int fd = ::open(c->output.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd < 0) {
    *error = "cannot create " + c->output;
    return false;
  }
  std::vector<char*> args;
  for (auto& a : c->argv) args.push_back(a.data());
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) {
    ::close(fd);
    *error = "fork failed";
    return false;
  }
  if (pid == 0) {
    dup2(fd, 1);
    dup2(fd, 2);
    ::close(fd);
    const int devnull = ::open("/dev/null", O_RDONLY);
    if (devnull >= 0) dup2(devnull, 0);
    if (chdir(cwd.c_str()) != 0) _exit(126);
    execv(args[0], args.data());
    std::fprintf(stderr, "ohrp_run: cannot execute %s: %s\n", args[0], std::strerror(errno));
    _exit(127);
  }
  ::close(fd);
  c->pid = pid;
  return true;
}

void Reap(Child* c) {
  if (c->pid <= 0) c->done = true;  // never started: nothing to wait for
  if (c->done) return;
  int st = 0;
  if (waitpid(c->pid, &st, WNOHANG) == c->pid) {
    c->done = true;
    c->exit_code = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
  }
}

void Echo(Child* c, bool echo) {
  std::ifstream in(c->output);
  in.seekg(c->echoed);
  std::string line;
  while (std::getline(in, line)) {
    if (in.eof()) break;  // a partial line: wait for the rest
    c->echoed = in.tellg();
    if (echo) std::fprintf(stderr, "  [%s] %s\n", c->label.c_str(), line.c_str());
  }
}

void Stop(Child* c, int sig) {
  if (!c->done && c->pid > 0) kill(c->pid, sig);
}

void WaitAll(std::vector<Child*> cs, double deadline, bool echo) {
  while (ohrp::MonotonicSeconds() < deadline) {
    bool all = true;
    for (Child* c : cs) {
      Reap(c);
      Echo(c, echo);
      all = all && c->done;
    }
    if (all) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

std::string EveryControllerRefused(const std::vector<Child>& ctl) {
  std::string said;
  for (const Child& c : ctl) {
    if (!c.done || (c.exit_code != 2 && c.exit_code != 3)) return "";
    said += (said.empty() ? "" : ", ") + c.label + ": exit " + std::to_string(c.exit_code);
  }
  return said;
}

}  // namespace ohrp::runner
