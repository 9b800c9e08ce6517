// RobotAdaptor: the controller's end of the robot segment, open / read / write / close
// (handshake: layout.h).
#include <unistd.h>

#include <algorithm>
#include <boost/interprocess/mapped_region.hpp>
#include <cmath>
#include <memory>
#include <string>

#include "attach.h"
#include "segment_guard.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/checks.h"
#include "signal_word.h"
#include "sync.h"

namespace bip = boost::interprocess;

namespace ohrp::shm {
namespace {

constexpr int kTakeOverAttempts = 8;  // CAS rounds when the controller slot changes under us

std::string Quoted(const std::string& segment_name) { return "segment '" + segment_name + "'"; }

}  // namespace

RobotAdaptor::~RobotAdaptor() { close(); }

//---------------- open ----------------

Status RobotAdaptor::open(const std::string& segment_name, const AdaptorOptions& options) {
  close();
  if (!(options.slice > 0.0) || !(options.read_timeout >= 0.0) || !std::isfinite(options.slice) ||
      !std::isfinite(options.read_timeout)) {
    return {Error::kInvalidConfig, "AdaptorOptions: slice must be > 0 and read_timeout >= 0 [s]"};
  }
  const std::string where = Quoted(segment_name);
  std::unique_ptr<bip::mapped_region> region;
  SegmentHeader copy{};
  int fd = -1;
  const Status check = internal::AttachSegment(segment_name, /*writable=*/true,
                                               options.allow_other_owner, &region, &copy, &fd);
  if (!check.ok()) return check;
  struct Closer {  // until the adaptor keeps it
    int* fd;
    ~Closer() { internal::CloseDescriptor(fd); }
  } closer{&fd};
  auto* segment = static_cast<Segment*>(region->get_address());
  SegmentHeader& h = segment->header;

  // the wake-up words: only the bridge's values are ever waited on
  const uint32_t sensors_word = std::atomic_ref<uint32_t>(segment->sync.sensors_ready.word).load();
  const uint32_t commands_word =
      std::atomic_ref<uint32_t>(segment->sync.commands_ready.word).load();
  if (!internal::ValidSignalWord(sensors_word) || !internal::ValidSignalWord(commands_word)) {
    return {Error::kInvalidHeader,
            where + " has corrupted wake-up words (sensors_ready " + std::to_string(sensors_word) +
                ", commands_ready " + std::to_string(commands_word) +
                "; only 0..3 are written by the bridge): another process wrote into the "
                "segment; restart the producer"};
  }

  // claim the controller slot; a slot held by a dead controller is taken over
  const pid_t self = getpid();
  bool claimed = false;
  for (int attempt = 0; attempt < kTakeOverAttempts && !claimed; ++attempt) {
    pid_t holder = 0;
    if (internal::SwapControllerPid(h, &holder, self)) {
      claimed = true;
    } else if (holder == self || ProcessAlive(holder)) {
      return {Error::kControllerPresent, where + " already has a controller (pid " +
                                             std::to_string(holder) + "); stop it first"};
    } else {
      claimed = internal::SwapControllerPid(h, &holder, self);
    }
  }
  if (!claimed) {
    return {Error::kControllerPresent,
            where + ": the controller slot kept changing while attaching; retry"};
  }

  // keep a validated copy of the header; the pending sensors post (if any) is the cycle to
  // answer first, so it is left in place
  header_ = SanitizedHeader(copy);
  header_.state = internal::LoadState(h);
  header_.controller_pid = self;
  options_ = options;
  last_cycle_ = 0;
  have_cycle_ = false;
  fault_ = SegmentFault::kNone;
  wait_typical_ns_ = 0;
  segment_ = segment;
  region_ = region.release();
  fd_ = fd;
  fd = -1;
  watch_ = internal::WatchMapping(static_cast<bip::mapped_region*>(region_)->get_address(),
                                  static_cast<bip::mapped_region*>(region_)->get_size(), true);
  return Status::Ok();
}

//---------------- cycle ----------------

ReadResult RobotAdaptor::FaultResult() const {
  return fault_ == SegmentFault::kWakeUpWords ? ReadResult::kSyncCorrupted
                                              : ReadResult::kSegmentCorrupted;
}

ReadResult RobotAdaptor::Checked(ReadResult r) {
  if (fault_ == SegmentFault::kNone) {
    fault_ = internal::CheckSegment(*segment_, header_.producer_pid, fd_, watch_);
  }
  return fault_ == SegmentFault::kNone ? r : FaultResult();
}

ReadResult RobotAdaptor::read(SensorBlock* out) {
  if (segment_ == nullptr) return ReadResult::kNotOpen;
  SegmentHeader& h = segment_->header;
  // the segment first: a truncated or scribbled one also looks dropped or ended
  if (Checked(ReadResult::kOk) != ReadResult::kOk) return FaultResult();
  if (dropped()) return Checked(ReadResult::kDropped);
  if (internal::IsEnded(internal::LoadState(h))) return Checked(ReadResult::kProducerStopped);

  const int64_t start = MonotonicNs();
  int64_t deadline = start + internal::SecondsToNs(options_.read_timeout);
  const int64_t slice_ns = std::max<int64_t>(internal::SecondsToNs(options_.slice), 1000000);
  for (int64_t now = start;; now = MonotonicNs()) {
    const int64_t until = std::min(deadline, now + slice_ns);
    const internal::SignalResult r =
        internal::Wait(&segment_->sync.sensors_ready, until, &wait_typical_ns_);
    if (r == internal::SignalResult::kCorrupt) {
      if (Checked(ReadResult::kOk) == ReadResult::kOk) fault_ = SegmentFault::kWakeUpWords;
      return FaultResult();
    }
    if (r == internal::SignalResult::kSignalled) {
      if (dropped()) return Checked(ReadResult::kDropped);
      if (internal::IsEnded(internal::LoadState(h))) return Checked(ReadResult::kProducerStopped);
      const auto copy = [this](const SensorBlock* src, SensorBlock* dst) {
        internal::CopySensors(src, dst, header_);
      };
      switch (
          internal::SeqlockCopy(&segment_->sensors, out, copy, header_.producer_pid, deadline)) {
        case internal::CopyResult::kOk:
          // a copy of zero pages (the file truncated during it) is no sensor block
          if (internal::MappingLost(watch_)) return Checked(ReadResult::kSegmentCorrupted);
          // a post that came while this process was still copying the block it announced (the
          // producer published twice before the copy) announces a block already returned: the
          // same cycle is never returned twice, the wait goes on for the next
          // A paused producer's heartbeat (status::kPaused, the same cycle again) restarts the
          // wait: a pause is not a dead producer.
          if (have_cycle_ && out->cycle == last_cycle_) {
            if (out->status & status::kPaused)
              deadline = MonotonicNs() + internal::SecondsToNs(options_.read_timeout);
            continue;
          }
          last_cycle_ = out->cycle;
          have_cycle_ = true;
          return ReadResult::kOk;
        case internal::CopyResult::kWriterGone:
          return Checked(ReadResult::kProducerGone);
        case internal::CopyResult::kTimeout:
          return Checked(ReadResult::kTimeout);
      }
    }
    // the slice ended: check the segment, the producer, then the deadline
    if (Checked(ReadResult::kOk) != ReadResult::kOk) return FaultResult();
    if (!ProcessAlive(header_.producer_pid)) return Checked(ReadResult::kProducerGone);
    if (dropped()) return Checked(ReadResult::kDropped);
    if (internal::IsEnded(internal::LoadState(h))) return Checked(ReadResult::kProducerStopped);
    if (MonotonicNs() >= deadline) return ReadResult::kTimeout;
  }
}

ReadResult RobotAdaptor::write(const CommandBlock& commands) {
  if (segment_ == nullptr) return ReadResult::kNotOpen;
  if (fault_ != SegmentFault::kNone) return FaultResult();
  if (dropped()) return Checked(ReadResult::kDropped);
  if (internal::IsEnded(internal::LoadState(segment_->header))) {
    return Checked(ReadResult::kProducerStopped);
  }
  CommandBlock& block = segment_->commands;
  const uint64_t odd = internal::SeqlockBegin(&block);
  // the caller's njoint and its first njoint joints; seq and answers_cycle belong to the bridge
  const int njoint = std::clamp(commands.njoint, 0, kMaxJoints);
  block.njoint = njoint;
  block.pad0 = 0;
  block.guard = commands.guard;
  block.guard.pad0 = 0;
  block.guard.link_a[kNameLen - 1] = block.guard.link_b[kNameLen - 1] = '\0';
  internal::CopyElements<JointCommand>(&commands, &block, offsetof(CommandBlock, joint), njoint);
  std::atomic_ref<uint64_t>(block.answers_cycle).store(last_cycle_, std::memory_order_relaxed);
  internal::SeqlockEnd(&block, odd);
  if (!internal::Post(&segment_->sync.commands_ready)) {
    if (Checked(ReadResult::kOk) == ReadResult::kOk) fault_ = SegmentFault::kWakeUpWords;
    return FaultResult();
  }
  // commands written into zero pages (the file truncated meanwhile) reach nobody
  if (internal::MappingLost(watch_)) return Checked(ReadResult::kSegmentCorrupted);
  return ReadResult::kOk;
}

uint32_t RobotAdaptor::published_status() const {
  if (segment_ == nullptr) return 0;
  // one aligned word: no torn value, whatever the seqlock's state
  return std::atomic_ref<uint32_t>(segment_->sensors.status).load(std::memory_order_acquire);
}

bool RobotAdaptor::dropped() const {
  if (segment_ == nullptr) return false;
  return internal::LoadControllerPid(segment_->header) != header_.controller_pid;
}

ProducerState RobotAdaptor::producer_state() const {
  if (segment_ == nullptr) return ProducerState::kStopped;
  return static_cast<ProducerState>(internal::LoadState(segment_->header));
}

//---------------- images ----------------

bool RobotAdaptor::request_images(uint32_t cameras) {
  if (segment_ == nullptr) return false;
  if (header_.ncamera < 32 && (cameras >> header_.ncamera) != 0) return false;
  return RequestImages(segment_->images.requests, getpid(), cameras);
}

ImageResult RobotAdaptor::read_image(int camera, uint64_t after_frame, ImageSlot* out) const {
  if (segment_ == nullptr) return ImageResult::kNotOpen;
  return ReadLatestImage(segment_, camera, after_frame, out);
}

//---------------- close ----------------

void RobotAdaptor::close() {
  if (segment_ == nullptr) return;
  RequestImages(segment_->images.requests, getpid(), 0);  // withdraw this process's request
  pid_t self = getpid();
  internal::SwapControllerPid(segment_->header, &self, 0);  // only our own claim is released
  internal::UnwatchMapping(watch_);
  watch_ = -1;
  internal::CloseDescriptor(&fd_);
  delete static_cast<bip::mapped_region*>(region_);
  segment_ = nullptr;
  region_ = nullptr;
  have_cycle_ = false;
}

}  // namespace ohrp::shm
