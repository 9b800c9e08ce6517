// Real-time set-up (see realtime.h).
#include "shm_bridge/realtime.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <cerrno>
#include <cstring>

namespace ohrp::rt {
namespace {

// touches `kb` KiB of stack below the caller, one write per page, so those pages are mapped
// (and, with mlockall, stay resident) before the loop runs
__attribute__((noinline)) void PrefaultStack(int kb) {
  constexpr int kMaxKb = 1024;
  volatile unsigned char buffer[kMaxKb * 1024];
  const int bytes = (kb < kMaxKb ? kb : kMaxKb) * 1024;
  for (int i = 0; i < bytes; i += 4096) buffer[i] = 0;
  asm volatile("" : : "r"(buffer) : "memory");  // the writes stay
}

}  // namespace

std::string RtReport::Describe() const {
  std::string s = fifo ? "SCHED_FIFO " + std::to_string(priority) : std::string("SCHED_OTHER");
  s += memory_locked ? ", memory locked" : ", memory not locked";
  return s;
}

RtReport SetUpRealTime(const RtSettings& settings) {
  RtReport r;
  if (settings.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      r.memory_locked = true;
    } else {
      r.warnings.push_back(std::string("mlockall refused (") + std::strerror(errno) +
                           "): page faults may delay the loop; run as root or raise "
                           "RLIMIT_MEMLOCK (ulimit -l)");
    }
  }
  if (settings.stack_prefault_kb > 0) PrefaultStack(settings.stack_prefault_kb);
  // a small timer slack: the sleeps end when asked, not up to 50 us later (SCHED_OTHER)
  if (settings.timer_slack_ns > 0 &&
      prctl(PR_SET_TIMERSLACK, static_cast<unsigned long>(settings.timer_slack_ns), 0, 0, 0) != 0) {
    r.warnings.push_back(std::string("timer slack ") + std::to_string(settings.timer_slack_ns) +
                         " ns refused (" + std::strerror(errno) +
                         "): the loop's sleeps may end up to the default slack late");
  }
  r.timer_slack_ns = prctl(PR_GET_TIMERSLACK, 0, 0, 0, 0);
  if (settings.priority > 0) {
    sched_param sp{};
    sp.sched_priority = settings.priority;
    const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (err == 0) {
      r.fifo = true;
      r.priority = settings.priority;
    } else {
      r.warnings.push_back(std::string("SCHED_FIFO ") + std::to_string(settings.priority) +
                           " refused (" + std::strerror(err) +
                           "): the loop runs SCHED_OTHER; run as root, grant CAP_SYS_NICE or "
                           "raise RLIMIT_RTPRIO (ulimit -r)");
    }
  }
  return r;
}

}  // namespace ohrp::rt
