// AttachSegment: map a robot segment by name and check it (attach.h).
#include "attach.h"

#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <boost/interprocess/exceptions.hpp>
#include <cstdlib>
#include <boost/interprocess/shared_memory_object.hpp>
#include <chrono>
#include <cstring>
#include <thread>

#include "segment_guard.h"
#include "shm_bridge/checks.h"
#include "sync.h"

namespace bip = boost::interprocess;

namespace ohrp::shm::internal {
namespace {

constexpr double kNotReadyWait = 1.0;   // [s] how long an attach waits for a producer in kCreating
constexpr double kNotReadyPoll = 0.01;  // [s] poll period of that wait

void Pause() { std::this_thread::sleep_for(std::chrono::duration<double>(kNotReadyPoll)); }

// "uid 65534 (nobody)"
std::string DescribeUid(uid_t uid) {
  std::string text = "uid " + std::to_string(uid);
  passwd entry{};
  passwd* found = nullptr;
  char buf[1024];
  if (getpwuid_r(uid, &entry, buf, sizeof(buf), &found) == 0 && found != nullptr) {
    text += std::string(" (") + found->pw_name + ")";
  }
  return text;
}

bool ForeignAllowed(bool allow_other_owner) {
  if (allow_other_owner) return true;
  const char* env = std::getenv(kAllowForeignSegmentEnv);
  return env != nullptr && std::string(env) == "1";
}

// Opens the object of `segment_name`. A file of 0 bytes is one a producer is creating (it
// creates the object, then sizes it): it is opened again (the name may be replaced meanwhile)
// until it has a size or `deadline_ns` passes. Returns kNoSegment or kOk; throws what boost
// throws for other errors.
Status OpenObject(const std::string& segment_name, const std::string& object_name,
                  bip::mode_t mode, int64_t deadline_ns, bip::shared_memory_object* shm,
                  bip::offset_t* size) {
  for (;;) {
    try {
      *shm = bip::shared_memory_object(bip::open_only, object_name.c_str(), mode);
    } catch (const bip::interprocess_exception& e) {
      if (e.get_error_code() != bip::not_found_error) throw;
      return {Error::kNoSegment, "no segment '" + segment_name + "' (/dev/shm/" + object_name +
                                     "): is sim_host or hw_driver running with --segment " +
                                     segment_name + "?"};
    }
    *size = 0;
    shm->get_size(*size);
    if (*size != 0 || MonotonicNs() >= deadline_ns) return Status::Ok();
    Pause();
  }
}

// kForeignOwner when the file of `fd` belongs to another user than this process's effective
// uid and that is not allowed
Status CheckOwner(int fd, const std::string& where, const std::string& object_name,
                  bool allow_other_owner) {
  struct stat st {};
  if (fstat(fd, &st) != 0) {
    return {Error::kSystem, where + " (/dev/shm/" + object_name + "): fstat failed"};
  }
  if (st.st_uid == geteuid() || ForeignAllowed(allow_other_owner)) return Status::Ok();
  return {Error::kForeignOwner,
          where + " (/dev/shm/" + object_name + ") belongs to " + DescribeUid(st.st_uid) +
              ", not to this process's " + DescribeUid(geteuid()) +
              ": another user may have created the name first to feed this program its "
              "sensors; refused. Remove the file or choose another --segment, or set " +
              kAllowForeignSegmentEnv + "=1 to attach anyway"};
}

// true while the producer has not finished its header: state kCreating and the magic is either
// still zero (fresh object) or complete, and the producer (when known) is alive
bool StillCreating(const SegmentHeader& h) {
  const uint32_t state = LoadState(const_cast<SegmentHeader&>(h));
  if (state != static_cast<uint32_t>(ProducerState::kCreating)) return false;
  static constexpr char kZero[sizeof(kMagic)] = {};
  const bool magic_ok = std::memcmp(h.magic, kMagic, sizeof(kMagic)) == 0 ||
                        std::memcmp(h.magic, kZero, sizeof(kMagic)) == 0;
  return magic_ok && (h.producer_pid == 0 || ProcessAlive(h.producer_pid));
}

}  // namespace

Status AttachSegment(const std::string& segment_name, bool writable, bool allow_other_owner,
                     std::unique_ptr<bip::mapped_region>* region, SegmentHeader* checked,
                     int* fd) {
  region->reset();
  *fd = -1;
  const std::string object_name = SegmentObjectName(segment_name);
  const std::string where = "segment '" + segment_name + "'";
  const bip::mode_t mode = writable ? bip::read_write : bip::read_only;
  // a producer still creating the segment (sizing it, writing its header) gets a moment
  const int64_t ready_deadline = MonotonicNs() + SecondsToNs(kNotReadyWait);
  std::unique_ptr<bip::mapped_region> mapped;
  int kept = -1;
  try {
    // the object, its owner and its size (mapping a short object would fault on access)
    bip::shared_memory_object shm;
    bip::offset_t size = 0;
    Status opened = OpenObject(segment_name, object_name, mode, ready_deadline, &shm, &size);
    if (!opened.ok()) return opened;
    opened = CheckOwner(shm.get_mapping_handle().handle, where, object_name, allow_other_owner);
    if (!opened.ok()) return opened;
    if (size == 0) {
      return {Error::kProducerNotReady,
              where + " (/dev/shm/" + object_name + ") is still empty (0 bytes) after " +
                  std::to_string(kNotReadyWait) +
                  " s: a producer is creating it, or died while creating it; retry, or "
                  "restart the producer"};
    }
    if (size < static_cast<bip::offset_t>(sizeof(Segment))) {
      SegmentHeader empty{};
      return CheckHeader(empty, static_cast<uint64_t>(std::max<bip::offset_t>(size, 0)),
                         segment_name);
    }
    mapped = std::make_unique<bip::mapped_region>(shm, mode, 0, sizeof(Segment));
    kept = KeepDescriptor(shm.get_mapping_handle().handle);
    if (kept < 0) return {Error::kSystem, where + " (/dev/shm/" + object_name + "): dup failed"};
  } catch (const bip::interprocess_exception& e) {
    return {Error::kSystem, where + " (/dev/shm/" + object_name + "): " + e.what()};
  }
  struct Closer {
    int* fd;
    ~Closer() { CloseDescriptor(fd); }
  } closer{&kept};
  const auto* segment = static_cast<const Segment*>(mapped->get_address());
  const SegmentHeader& h = segment->header;

  // a producer still writing its header gets the rest of the moment
  while (StillCreating(h) && MonotonicNs() < ready_deadline) Pause();

  // identity and layout, then the producer's life
  Status check = CheckHeader(h, sizeof(Segment), segment_name);
  if (!check.ok()) return check;
  const uint32_t state = LoadState(const_cast<SegmentHeader&>(h));
  if (state == static_cast<uint32_t>(ProducerState::kCreating)) {
    return {Error::kProducerNotReady,
            where + " is still being created by producer pid " + std::to_string(h.producer_pid) +
                " after " + std::to_string(kNotReadyWait) + " s; retry, or restart the producer"};
  }
  if (!ProcessAlive(h.producer_pid)) {
    return {Error::kProducerDead, "stale " + where + ": its producer pid " +
                                      std::to_string(h.producer_pid) +
                                      " is gone; restart the producer"};
  }
  if (IsEnded(state)) {
    return {Error::kProducerStopped,
            where + " belongs to producer pid " + std::to_string(h.producer_pid) + " that has " +
                (state == static_cast<uint32_t>(ProducerState::kFailed) ? "failed" : "stopped") +
                "; restart the producer"};
  }
  if (state != static_cast<uint32_t>(ProducerState::kRunning)) {
    return {Error::kNotASegment, where + " has unknown producer state " + std::to_string(state)};
  }

  // the values, checked on a copy so that what was checked is what is kept
  *checked = h;
  check = CheckHeaderValues(*checked, segment_name);
  if (!check.ok()) return check;
  *region = std::move(mapped);
  *fd = kept;
  kept = -1;
  return Status::Ok();
}

}  // namespace ohrp::shm::internal
