// Names and small process helpers shared by both ends of the bridge (bridge.h).
#include "shm_bridge/bridge.h"
#include "shm_bridge/controller_loss.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
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
    case Error::kInvalidHeader:
      return "invalid header";
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
    case Error::kForeignOwner:
      return "segment owned by another user";
  }
  return "unknown error";
}

const char* SegmentFaultText(SegmentFault f) {
  switch (f) {
    case SegmentFault::kNone:
      return "the segment is intact";
    case SegmentFault::kWakeUpWords:
      return "the segment's wake-up words were overwritten by another process";
    case SegmentFault::kHeader:
      return "the segment's header (magic, producer pid or state) was overwritten by another "
             "process";
    case SegmentFault::kTruncated:
      return "the segment's file was truncated by another process (its memory is gone)";
  }
  return "the segment is corrupted";
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
    case ReadResult::kDropped:
      return "dropped by the producer";
    case ReadResult::kSyncCorrupted:
      return "the segment's wake-up words are corrupted (another process wrote into the "
             "segment)";
    case ReadResult::kSegmentCorrupted:
      return "the segment's file was truncated or its header overwritten (another process "
             "wrote into the segment)";
  }
  return "unknown";
}

std::string SegmentObjectName(const std::string& segment_name) { return "ohrp_" + segment_name; }

bool ProcessAlive(pid_t pid) {
  if (pid <= 0) return false;  // kill(0 or -n, 0) would address process groups
  if (kill(pid, 0) != 0 && errno != EPERM) return false;
  // a zombie (dead, not yet reaped by its parent) still answers kill(): read its state,
  // the field after the parenthesised command name in /proc/<pid>/stat
  char path[32];
  std::snprintf(path, sizeof(path), "/proc/%d/stat", static_cast<int>(pid));
  const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return true;  // no procfs: trust kill()
  char buf[256];
  const ssize_t n = ::read(fd, buf, sizeof(buf) - 1);
  ::close(fd);
  if (n <= 0) return true;
  buf[n] = 0;
  const char* paren = std::strrchr(buf, ')');
  return !(paren && paren[1] == ' ' && (paren[2] == 'Z' || paren[2] == 'X'));
}

//---------------- the controller-loss policy ----------------

const char* ControllerLossName(ControllerLoss loss) {
  switch (loss) {
    case ControllerLoss::kEnd:
      return "end";
    case ControllerLoss::kWait:
      return "wait";
    case ControllerLoss::kContinue:
      return "continue";
  }
  return "?";
}

bool ParseControllerLoss(const std::string& text, ControllerLoss* out) {
  for (ControllerLoss l : {ControllerLoss::kEnd, ControllerLoss::kWait, ControllerLoss::kContinue}) {
    if (text == ControllerLossName(l)) {
      *out = l;
      return true;
    }
  }
  return false;
}

}  // namespace ohrp::shm
