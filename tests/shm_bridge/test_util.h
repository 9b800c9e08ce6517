// Helpers for the shm_bridge tests: unique segment names, a small producer config, forked
// children with exit codes, pipes for ordering steps across processes.
#pragma once

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <functional>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/clock.h"  // MonotonicSeconds: system-wide, comparable across processes

namespace ohrp::shm::testing {

// a segment name unique to this test process and `tag`
inline std::string UniqueSegment(const std::string& tag) {
  return "test_" + tag + "_" + std::to_string(getpid());
}

inline void RemoveSegment(const std::string& segment_name) {
  boost::interprocess::shared_memory_object::remove(SegmentObjectName(segment_name).c_str());
}

inline std::string DevShmPath(const std::string& segment_name) {
  return "/dev/shm/" + SegmentObjectName(segment_name);
}

// a valid three-joint configuration
inline ProducerConfig SmallConfig(const std::string& segment_name) {
  ProducerConfig c;
  c.segment_name = segment_name;
  c.kind = ProducerKind::kSimulation;
  c.robot_name = "testbot";
  c.joint_names = {"hip", "knee", "ankle"};
  c.force_names = {"foot_ft"};
  c.imu_names = {"base_imu"};
  c.q_min = {-1.0, -2.0, -0.5};
  c.q_max = {1.0, 0.0, 0.5};
  c.tau_max = {100.0, 80.0, 40.0};
  c.default_kp = {300.0, 200.0, 100.0};
  c.default_kd = {3.0, 2.0, 1.0};
  c.physics_period = 0.001;
  c.control_period = 0.005;
  c.read_timeout_hint = 1.0;
  return c;
}

// Runs `body` in a forked child that exits with its return value (99 on an exception). The
// child never returns into the test framework.
inline pid_t Spawn(const std::function<int()>& body) {
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

// Waits for child `pid` up to `timeout` [s]: its exit code, 128 + signal when killed, or -1 on
// timeout (the child is then killed and reaped).
inline int WaitExit(pid_t pid, double timeout = 5.0) {
  const double deadline = MonotonicSeconds() + timeout;
  for (;;) {
    int status = 0;
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      if (WIFEXITED(status)) return WEXITSTATUS(status);
      if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
      return -2;
    }
    if (r < 0) return -3;
    if (MonotonicSeconds() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    usleep(1000);
  }
}

// Polls `condition` every millisecond until it holds or `timeout` [s] passes.
inline bool WaitFor(const std::function<bool()>& condition, double timeout = 5.0) {
  const double deadline = MonotonicSeconds() + timeout;
  while (!condition()) {
    if (MonotonicSeconds() > deadline) return false;
    usleep(1000);
  }
  return true;
}

// Opens `segment_name` as a controller, retrying while the producer is not there yet.
inline Status OpenWhenReady(RobotAdaptor* adaptor, const std::string& segment_name,
                            const AdaptorOptions& options = {}, double timeout = 5.0) {
  const double deadline = MonotonicSeconds() + timeout;
  for (;;) {
    Status s = adaptor->open(segment_name, options);
    if (s.code != Error::kNoSegment || MonotonicSeconds() > deadline) return s;
    usleep(1000);
  }
}

// A pipe used to order steps between a parent and a child: one byte is one signal.
class Pipe {
 public:
  Pipe() {
    if (pipe(fds_) != 0) fds_[0] = fds_[1] = -1;
  }
  ~Pipe() {
    for (int fd : fds_) {
      if (fd >= 0) close(fd);
    }
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;

  bool Send(char c = 'x') { return ::write(fds_[1], &c, 1) == 1; }
  // true when a byte arrived within `timeout` [s]
  bool Receive(double timeout = 5.0) {
    pollfd p{fds_[0], POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(timeout * 1000)) != 1) return false;
    char c = 0;
    return ::read(fds_[0], &c, 1) == 1;
  }

 private:
  int fds_[2] = {-1, -1};
};

// Maps the whole object of `segment_name` read-write, to corrupt fields on purpose.
class RawSegment {
 public:
  explicit RawSegment(const std::string& segment_name)
      : shm_(boost::interprocess::open_only, SegmentObjectName(segment_name).c_str(),
             boost::interprocess::read_write),
        region_(shm_, boost::interprocess::read_write) {}
  Segment* get() { return static_cast<Segment*>(region_.get_address()); }

 private:
  boost::interprocess::shared_memory_object shm_;
  boost::interprocess::mapped_region region_;
};

}  // namespace ohrp::shm::testing
