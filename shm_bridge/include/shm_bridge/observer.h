// The observer: a read-only view of a running robot segment for viewers, loggers and
// monitors. Many observers may watch one segment at once; none of them takes the controller
// slot, posts or waits on the handshake, or writes a byte into the segment (the mapping is
// read-only), so an observer can never slow the lock-step or disturb the controller.
//
// The one exception to "never writes": request_images, on demand, maps the page of the image
// requests (layout.h) for writing and sets this process's own entry there; close withdraws it.
//
// An observer sees each published sensor block through the seqlock (never torn), and the last
// command block the controller wrote. It polls: a wait for the next cycle sleeps `poll` between
// looks, so it may skip cycles when it is slower than the producer (the cycle counter says how
// many). The calls do not allocate, throw or log.
#pragma once

#include <sys/types.h>

#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/images.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm {

struct ObserverOptions {
  double poll = 0.0005;  // [s] sleep between looks while waiting for the next cycle
  bool allow_other_owner = false;  // as AdaptorOptions::allow_other_owner (bridge.h)
};

class Observer {
 public:
  Observer() = default;
  ~Observer();  // close()
  Observer(const Observer&) = delete;
  Observer& operator=(const Observer&) = delete;

  // Maps the segment read-only and checks it as RobotAdaptor::open does (owner, identity,
  // layout, producer alive and running, header values), without claiming anything.
  Status open(const std::string& segment_name, const ObserverOptions& options = {});

  // Waits up to `timeout` [s] for a sensor block newer than the last one this observer
  // returned (the first call returns the block published last, if any), and copies it into
  // `*out` (the entries in use). kOk, kTimeout, kProducerGone, kProducerStopped or kNotOpen;
  // kSyncCorrupted or kSegmentCorrupted once the segment is found faulty (checked at each look,
  // as RobotAdaptor::read does: a truncated file ends the observer with a result, no SIGBUS).
  // Once the producer has stopped, the last block it published is still returned once.
  ReadResult read(SensorBlock* out, double timeout);

  // Copies the last command block the controller wrote (its first njoint joints) into `*out`;
  // false when none was written yet (answers_cycle and njoint 0) or the copy did not settle.
  bool commands(CommandBlock* out) const;

  // Asks the producer for the images of `cameras` (bit i: camera i; 0 withdraws), as
  // RobotAdaptor::request_images does; the first call maps the requests' page (4 KiB) for
  // writing, so it is a set-up call (it may allocate). False when not open, a bit names no
  // camera, the page cannot be mapped, or every request entry is taken.
  bool request_images(uint32_t cameras);

  // The latest frame of `camera` newer than `after_frame` (images.h: ReadLatestImage).
  ImageResult read_image(int camera, uint64_t after_frame, ImageSlot* out) const;

  // The attached controller's pid now (0: none).
  pid_t controller_pid() const;
  ProducerState producer_state() const;

  void close();
  bool is_open() const { return segment_ != nullptr; }
  // A copy of the header, validated at open (names NUL-terminated, counts clamped).
  const SegmentHeader& header() const { return header_; }

 private:
  const Segment* segment_ = nullptr;
  void* region_ = nullptr;  // boost mapped_region, owned
  void* requests_region_ = nullptr;  // the requests' page mapped writable (request_images), owned
  ImageRequest* requests_ = nullptr;  // in that page
  std::string segment_name_;
  SegmentHeader header_{};
  ObserverOptions options_;
  uint64_t last_seq_ = 0;  // seqlock value of the last block returned (0: none yet)
  int fd_ = -1;            // the segment's file, for fstat
  int watch_ = -1;         // the mapping watch's slot of the segment (segment_guard.h)
  int requests_watch_ = -1;  // and of the requests' page
  SegmentFault fault_ = SegmentFault::kNone;
};

}  // namespace ohrp::shm
