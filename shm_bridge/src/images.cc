// Camera images: publish, read the latest frame, requests (images.h; layout: layout.h).
#include "shm_bridge/images.h"

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>

#include "shm_bridge/bridge.h"
#include "sync.h"

namespace ohrp::shm {
namespace {

// the number of cameras of the header, clamped to the layout (the header may be a reader's
// view of another process's memory)
int CameraCount(const SegmentHeader& h) {
  return std::clamp<int32_t>(h.ncamera, 0, kMaxCameras);  // written before kRunning, then fixed
}

std::size_t Pixels(int32_t width, int32_t height) {
  const int32_t w = std::clamp<int32_t>(width, 0, kMaxImageWidth);
  const int32_t h = std::clamp<int32_t>(height, 0, kMaxImageHeight);
  return static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
}

// the slot's fields and its first pixels, the counts read from the source and clamped (a copy
// that races the writer is thrown away by the seqlock check, but must not overrun meanwhile)
void CopySlot(const ImageSlot* src, ImageSlot* dst) {
  constexpr std::size_t kHead = offsetof(ImageSlot, rgb);
  std::memcpy(static_cast<void*>(dst), static_cast<const void*>(src), kHead);
  const std::size_t n = Pixels(dst->width, dst->height);
  std::memcpy(dst->rgb, src->rgb, 3 * n);
  if (dst->has_depth != 0) std::memcpy(dst->depth, src->depth, sizeof(float) * n);
}

}  // namespace

const char* ImageResultName(ImageResult r) {
  switch (r) {
    case ImageResult::kOk: return "ok";
    case ImageResult::kNoFrame: return "no frame";
    case ImageResult::kBusy: return "busy";
    case ImageResult::kBadCamera: return "bad camera";
    case ImageResult::kBadSize: return "bad size";
    case ImageResult::kNotOpen: return "not open";
  }
  return "unknown";
}

ImageResult PublishImage(Segment* segment, int camera, double time, int width, int height,
                         const uint8_t* rgb, const float* depth) {
  const SegmentHeader& h = segment->header;
  if (camera < 0 || camera >= CameraCount(h)) return ImageResult::kBadCamera;
  const CameraInfo& info = h.cameras[camera];
  if (width <= 0 || height <= 0 || width > info.width || height > info.height ||
      width > kMaxImageWidth || height > kMaxImageHeight || rgb == nullptr) {
    return ImageResult::kBadSize;
  }
  CameraImages& images = segment->images.camera[camera];
  std::atomic_ref<uint64_t> latest(images.latest);
  const uint64_t frame = latest.load(std::memory_order_relaxed) + 1;  // the only writer
  ImageSlot& slot = images.slot[frame % kImageSlots];

  const uint64_t odd = internal::SeqlockBegin(&slot);
  slot.frame = frame;
  slot.time = time;
  slot.width = width;
  slot.height = height;
  slot.has_depth = depth != nullptr ? 1u : 0u;
  slot.pad0 = 0;
  const std::size_t n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  std::memcpy(slot.rgb, rgb, 3 * n);
  if (depth != nullptr) std::memcpy(slot.depth, depth, sizeof(float) * n);
  internal::SeqlockEnd(&slot, odd);
  latest.store(frame, std::memory_order_release);
  return ImageResult::kOk;
}

ImageResult ReadLatestImage(const Segment* segment, int camera, uint64_t after_frame,
                            ImageSlot* out, double timeout) {
  if (camera < 0 || camera >= CameraCount(segment->header)) return ImageResult::kBadCamera;
  // the reader only loads; atomic_ref needs a non-const object
  auto& images = const_cast<CameraImages&>(segment->images.camera[camera]);
  std::atomic_ref<uint64_t> latest(images.latest);
  const int64_t deadline = MonotonicNs() + internal::SecondsToNs(timeout);
  for (uint32_t attempt = 1;; ++attempt) {
    const uint64_t frame = latest.load(std::memory_order_acquire);
    if (frame == 0 || frame <= after_frame) return ImageResult::kNoFrame;
    ImageSlot& slot = images.slot[frame % kImageSlots];
    std::atomic_ref<uint64_t> seq(slot.seq);
    const uint64_t before = seq.load(std::memory_order_acquire);
    if ((before & 1u) == 0) {
      CopySlot(&slot, out);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq.load(std::memory_order_relaxed) == before && out->frame > after_frame) {
        out->seq = before;
        return ImageResult::kOk;
      }
    }
    if (MonotonicNs() >= deadline) return ImageResult::kBusy;
    if (attempt % 16 == 0) sched_yield();
  }
}

bool RequestImages(ImageRequest* requests, pid_t pid, uint32_t cameras) {
  // the entry this process holds already
  for (int i = 0; i < kMaxImageRequesters; ++i) {
    std::atomic_ref<int32_t> owner(requests[i].pid);
    if (owner.load(std::memory_order_acquire) != pid) continue;
    if (cameras == 0) {
      std::atomic_ref<uint32_t>(requests[i].cameras).store(0, std::memory_order_release);
      owner.store(0, std::memory_order_release);
    } else {
      std::atomic_ref<uint32_t>(requests[i].cameras).store(cameras, std::memory_order_release);
    }
    return true;
  }
  if (cameras == 0) return true;  // nothing held, nothing to withdraw
  // a free entry, or one left by a dead process
  for (int i = 0; i < kMaxImageRequesters; ++i) {
    std::atomic_ref<int32_t> owner(requests[i].pid);
    int32_t holder = owner.load(std::memory_order_acquire);
    if (holder != 0 && ProcessAlive(holder)) continue;
    if (!owner.compare_exchange_strong(holder, pid, std::memory_order_acq_rel)) continue;
    std::atomic_ref<uint32_t>(requests[i].cameras).store(cameras, std::memory_order_release);
    return true;
  }
  return false;
}

uint32_t ImagesRequested(const ImageRequest* requests) {
  uint32_t wanted = 0;
  for (int i = 0; i < kMaxImageRequesters; ++i) {
    auto& entry = const_cast<ImageRequest&>(requests[i]);
    const uint32_t cameras =
        std::atomic_ref<uint32_t>(entry.cameras).load(std::memory_order_acquire);
    if (cameras == 0 || (cameras & ~wanted) == 0) continue;  // nothing new from this entry
    const int32_t pid = std::atomic_ref<int32_t>(entry.pid).load(std::memory_order_acquire);
    if (pid > 0 && ProcessAlive(pid)) wanted |= cameras;
  }
  return wanted;
}

}  // namespace ohrp::shm
