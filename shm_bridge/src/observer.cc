// Observer: a read-only view of a robot segment (observer.h).
#include "shm_bridge/observer.h"

#include <time.h>

#include <unistd.h>

#include <boost/interprocess/exceptions.hpp>
#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <cmath>
#include <cstddef>
#include <memory>

#include "attach.h"
#include "segment_guard.h"
#include "shm_bridge/checks.h"
#include "sync.h"

namespace bip = boost::interprocess;

namespace ohrp::shm {
namespace {

template <class Block>
Block* Mutable(const Block* b) {  // the seqlock reader only loads (the mapping is read-only)
  return const_cast<Block*>(b);
}

}  // namespace

Observer::~Observer() { close(); }

Status Observer::open(const std::string& segment_name, const ObserverOptions& options) {
  close();
  if (!(options.poll > 0.0) || !std::isfinite(options.poll)) {
    return {Error::kInvalidConfig, "ObserverOptions: poll must be > 0 [s]"};
  }
  std::unique_ptr<bip::mapped_region> region;
  SegmentHeader copy{};
  int fd = -1;
  const Status check = internal::AttachSegment(segment_name, /*writable=*/false,
                                               options.allow_other_owner, &region, &copy, &fd);
  if (!check.ok()) return check;
  fd_ = fd;
  watch_ = internal::WatchMapping(region->get_address(), region->get_size(), false);
  fault_ = SegmentFault::kNone;
  header_ = SanitizedHeader(copy);
  segment_name_ = segment_name;
  options_ = options;
  last_seq_ = 0;
  segment_ = static_cast<const Segment*>(region->get_address());
  region_ = region.release();
  return Status::Ok();
}

ReadResult Observer::read(SensorBlock* out, double timeout) {
  if (segment_ == nullptr) return ReadResult::kNotOpen;
  SegmentHeader& h = Mutable(&segment_->header)[0];
  std::atomic_ref<uint64_t> seq(Mutable(&segment_->sensors)->seq);
  const int64_t deadline = MonotonicNs() + internal::SecondsToNs(timeout);
  const timespec pause = internal::ToTimespec(std::max<int64_t>(internal::SecondsToNs(options_.poll), 1000));
  const auto faulty = [this] {
    if (fault_ == SegmentFault::kNone) {
      fault_ = internal::CheckSegment(*segment_, header_.producer_pid, fd_, watch_);
    }
    return fault_ != SegmentFault::kNone;
  };
  const auto fault_result = [this] {
    return fault_ == SegmentFault::kWakeUpWords ? ReadResult::kSyncCorrupted
                                                : ReadResult::kSegmentCorrupted;
  };
  for (;;) {
    if (faulty()) return fault_result();
    const bool ended = internal::IsEnded(internal::LoadState(h));
    const uint64_t now_seq = seq.load(std::memory_order_acquire);
    if (now_seq != 0 && now_seq != last_seq_) {
      // a block newer than the last one returned (or being written: the copy waits it out)
      const auto copy = [this](const SensorBlock* src, SensorBlock* dst) {
        internal::CopySensors(src, dst, header_);
      };
      switch (internal::SeqlockCopy(Mutable(&segment_->sensors), out, copy,
                                    header_.producer_pid, deadline)) {
        case internal::CopyResult::kOk:
          if (faulty()) return fault_result();  // e.g. a copy of zero pages
          if (out->seq != last_seq_) {
            last_seq_ = out->seq;
            return ReadResult::kOk;
          }
          break;
        case internal::CopyResult::kWriterGone:
          return ReadResult::kProducerGone;
        case internal::CopyResult::kTimeout:
          return ReadResult::kTimeout;
      }
    }
    if (ended) return ReadResult::kProducerStopped;
    if (!ProcessAlive(header_.producer_pid)) return ReadResult::kProducerGone;
    if (MonotonicNs() >= deadline) return ReadResult::kTimeout;
    nanosleep(&pause, nullptr);
  }
}

bool Observer::commands(CommandBlock* out) const {
  if (segment_ == nullptr) return false;
  const auto copy = [](const CommandBlock* src, CommandBlock* dst) {
    internal::CopyCommands(src, dst);
  };
  const int64_t deadline = MonotonicNs() + internal::SecondsToNs(0.01);
  if (internal::SeqlockCopy(Mutable(&segment_->commands), out, copy, 0, deadline) !=
      internal::CopyResult::kOk) {
    return false;
  }
  return out->njoint > 0 || out->answers_cycle > 0;
}

bool Observer::request_images(uint32_t cameras) {
  if (segment_ == nullptr) return false;
  if (header_.ncamera < 32 && (cameras >> header_.ncamera) != 0) return false;
  if (requests_ == nullptr) {
    if (cameras == 0) return true;  // nothing asked yet, nothing to withdraw
    static_assert(offsetof(Segment, images) % 4096 == 0 && offsetof(ImageArea, requests) == 0);
    try {
      bip::shared_memory_object shm(bip::open_only, SegmentObjectName(segment_name_).c_str(),
                                    bip::read_write);
      auto* page = new bip::mapped_region(shm, bip::read_write, offsetof(Segment, images),
                                          sizeof(ImageArea::requests));
      requests_region_ = page;
      requests_ = static_cast<ImageRequest*>(page->get_address());
      requests_watch_ = internal::WatchMapping(page->get_address(), page->get_size(), true);
    } catch (const bip::interprocess_exception&) {
      return false;
    }
  }
  return RequestImages(requests_, getpid(), cameras);
}

ImageResult Observer::read_image(int camera, uint64_t after_frame, ImageSlot* out) const {
  if (segment_ == nullptr) return ImageResult::kNotOpen;
  return ReadLatestImage(segment_, camera, after_frame, out);
}

pid_t Observer::controller_pid() const {
  if (segment_ == nullptr) return 0;
  return internal::LoadControllerPid(Mutable(&segment_->header)[0]);
}

ProducerState Observer::producer_state() const {
  if (segment_ == nullptr) return ProducerState::kStopped;
  return static_cast<ProducerState>(internal::LoadState(Mutable(&segment_->header)[0]));
}

void Observer::close() {
  if (segment_ == nullptr) return;
  if (requests_ != nullptr) RequestImages(requests_, getpid(), 0);  // withdraw our request
  internal::UnwatchMapping(requests_watch_);
  internal::UnwatchMapping(watch_);
  requests_watch_ = watch_ = -1;
  internal::CloseDescriptor(&fd_);
  delete static_cast<bip::mapped_region*>(requests_region_);
  requests_region_ = nullptr;
  requests_ = nullptr;
  delete static_cast<bip::mapped_region*>(region_);
  segment_ = nullptr;
  region_ = nullptr;
}

}  // namespace ohrp::shm
