// Camera images in the robot segment (layout: layout.h, "camera images"): the producer
// publishes frames into two seqlocked slots per camera and never waits; readers copy the latest
// complete frame and never see a torn one; programs say which cameras they want, so that the
// producer renders only while somebody asks.
//
// These are the functions behind Producer::PublishImage / ImagesRequested and
// RobotAdaptor::request_images / read_image (bridge.h) and the observer's (observer.h). None of
// them allocates, throws or logs: they may run in a control cycle.
#pragma once

#include <sys/types.h>

#include <cstdint>

#include "shm_bridge/layout.h"

namespace ohrp::shm {

enum class ImageResult {
  kOk,          // a frame was published / copied out
  kNoFrame,     // (read) the camera has no frame newer than the one asked after
  kBusy,        // (read) the producer kept rewriting the slot until the deadline: retry later
  kBadCamera,   // the camera index is outside [0, ncamera) of the header
  kBadSize,     // (publish) width x height is empty, or larger than the header's camera or
                // than the slots (kMaxImageWidth x kMaxImageHeight)
  kNotOpen,     // the end is not attached
};

const char* ImageResultName(ImageResult r);

// Producer side. Publishes a frame of camera `camera` captured at `time` [s]: `rgb` holds
// width x height x 3 bytes (RGB8, row-major, top row first), `depth` width x height distances
// [m] in the same order, or is null (no depth). The frame goes into the slot the readers are
// not pointed at, under its seqlock; then `latest` moves to it. Never waits. Only the segment's
// producer may call it (one writer per camera). Returns kOk, kBadCamera or kBadSize.
ImageResult PublishImage(Segment* segment, int camera, double time, int width, int height,
                         const uint8_t* rgb, const float* depth);

// Reader side. Copies the latest complete frame of `camera` into `*out` when its frame counter
// is greater than `after_frame` (0: any frame): the slot's fields and its first width x height
// pixels (and depths when has_depth); the rest of `*out` is left as it was. Retries while the
// producer rewrites the slot, up to `timeout` [s] (then kBusy). kOk, kNoFrame, kBusy or
// kBadCamera. `out` is large (ImageSlot, about 2 MB): allocate it once, outside the cycle.
ImageResult ReadLatestImage(const Segment* segment, int camera, uint64_t after_frame,
                            ImageSlot* out, double timeout = 0.02);

// Sets the cameras process `pid` asks for (bit i: camera i of the header; 0 withdraws its
// entry). The entry of `pid` is reused; otherwise a free entry, or one held by a dead process,
// is claimed. `requests` is the segment's array of kMaxImageRequesters entries. False when
// every entry is held by a live process (nothing changed); withdrawing always succeeds.
bool RequestImages(ImageRequest* requests, pid_t pid, uint32_t cameras);

// The cameras some live process asks for (OR of the entries of live pids).
uint32_t ImagesRequested(const ImageRequest* requests);

}  // namespace ohrp::shm
