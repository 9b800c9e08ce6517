// AttachSegment: map a robot segment by name and check it (attach.h).
#include "attach.h"

#include <algorithm>
#include <boost/interprocess/exceptions.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <chrono>
#include <cstring>
#include <thread>

#include "shm_bridge/checks.h"
#include "sync.h"

namespace bip = boost::interprocess;

namespace ohrp::shm::internal {
namespace {

constexpr double kNotReadyWait = 1.0;   // [s] how long an attach waits for a producer in kCreating
constexpr double kNotReadyPoll = 0.01;  // [s] poll period of that wait

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

Status AttachSegment(const std::string& segment_name, bool writable,
                     std::unique_ptr<bip::mapped_region>* region, SegmentHeader* checked) {
  region->reset();
  const std::string object_name = SegmentObjectName(segment_name);
  const std::string where = "segment '" + segment_name + "'";
  const bip::mode_t mode = writable ? bip::read_write : bip::read_only;
  std::unique_ptr<bip::mapped_region> mapped;
  try {
    // the object and its size (mapping a short object would fault on access)
    bip::shared_memory_object shm;
    try {
      shm = bip::shared_memory_object(bip::open_only, object_name.c_str(), mode);
    } catch (const bip::interprocess_exception& e) {
      if (e.get_error_code() != bip::not_found_error) throw;
      return {Error::kNoSegment, "no segment '" + segment_name + "' (/dev/shm/" + object_name +
                                     "): is sim_host or hw_driver running with --segment " +
                                     segment_name + "?"};
    }
    bip::offset_t size = 0;
    shm.get_size(size);
    if (size < static_cast<bip::offset_t>(sizeof(Segment))) {
      SegmentHeader empty{};
      return CheckHeader(empty, static_cast<uint64_t>(std::max<bip::offset_t>(size, 0)),
                         segment_name);
    }
    mapped = std::make_unique<bip::mapped_region>(shm, mode, 0, sizeof(Segment));
  } catch (const bip::interprocess_exception& e) {
    return {Error::kSystem, where + " (/dev/shm/" + object_name + "): " + e.what()};
  }
  const auto* segment = static_cast<const Segment*>(mapped->get_address());
  const SegmentHeader& h = segment->header;

  // a producer still writing its header gets a moment
  const int64_t ready_deadline = MonotonicNs() + SecondsToNs(kNotReadyWait);
  while (StillCreating(h) && MonotonicNs() < ready_deadline) {
    std::this_thread::sleep_for(std::chrono::duration<double>(kNotReadyPoll));
  }

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
  return Status::Ok();
}

}  // namespace ohrp::shm::internal
