// Names and small process helpers shared by both ends of the bridge (bridge.h).
#include "shm_bridge/bridge.h"

#include <signal.h>

#include <cerrno>
#include <string>

namespace ohrp::shm {

const char* ErrorName(Error e) {
  switch (e) {
    case Error::kOk:
      return "ok";
    case Error::kNoSegment:
      return "no segment";
    case Error::kNotASegment:
      return "not a segment";
    case Error::kLayoutMismatch:
      return "layout mismatch";
    case Error::kProducerNotReady:
      return "producer not ready";
    case Error::kProducerDead:
      return "producer dead";
    case Error::kProducerStopped:
      return "producer stopped";
    case Error::kControllerPresent:
      return "controller present";
    case Error::kSegmentBusy:
      return "segment busy";
    case Error::kInvalidConfig:
      return "invalid config";
    case Error::kSystem:
      return "system error";
  }
  return "unknown error";
}

const char* ReadResultName(ReadResult r) {
  switch (r) {
    case ReadResult::kOk:
      return "ok";
    case ReadResult::kTimeout:
      return "timeout";
    case ReadResult::kProducerGone:
      return "producer gone";
    case ReadResult::kProducerStopped:
      return "producer stopped";
    case ReadResult::kNotOpen:
      return "not open";
  }
  return "unknown";
}

std::string SegmentObjectName(const std::string& segment_name) { return "ohrp_" + segment_name; }

bool ProcessAlive(pid_t pid) {
  if (pid <= 0) return false;  // kill(0 or -n, 0) would address process groups
  return kill(pid, 0) == 0 || errno == EPERM;
}

}  // namespace ohrp::shm
