// Internals shared by the producer and the robot adaptor: the monotonic clock, the shared
// state and pids, and the seqlock of the data blocks (protocol: layout.h; the wake-up words
// are in signal_word.h). Everything here is real-time safe: no allocation, no exceptions, no
// logging.
#pragma once

#include <sched.h>
#include <sys/types.h>
#include <time.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "shm_bridge/bridge.h"
#include "shm_bridge/clock.h"
#include "shm_bridge/clock.h"  // MonotonicNs
#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

//---------------- monotonic time ----------------

inline constexpr int64_t kNsPerS = 1000000000;

// a duration [s] as [ns]; negative and NaN become 0, huge values saturate at ~30 years
inline int64_t SecondsToNs(double s) {
  if (!(s > 0.0)) return 0;
  if (s > 1e9) return static_cast<int64_t>(1e9) * kNsPerS;
  return static_cast<int64_t>(std::llround(s * 1e9));
}

inline timespec ToTimespec(int64_t ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(ns / kNsPerS);
  ts.tv_nsec = static_cast<long>(ns % kNsPerS);
  return ts;
}

//---------------- state and pids ----------------

inline uint32_t LoadState(SegmentHeader& h) {
  return std::atomic_ref<uint32_t>(h.state).load(std::memory_order_acquire);
}

inline bool IsEnded(uint32_t state) {
  return state == static_cast<uint32_t>(ProducerState::kStopped) ||
         state == static_cast<uint32_t>(ProducerState::kFailed);
}

inline pid_t LoadControllerPid(SegmentHeader& h) {
  return std::atomic_ref<int32_t>(h.controller_pid).load(std::memory_order_acquire);
}

// replaces the controller pid `expected` by `desired`; false when it was something else
inline bool SwapControllerPid(SegmentHeader& h, pid_t* expected, pid_t desired) {
  int32_t e = *expected;
  const bool ok = std::atomic_ref<int32_t>(h.controller_pid)
                      .compare_exchange_strong(e, desired, std::memory_order_acq_rel,
                                               std::memory_order_acquire);
  *expected = e;
  return ok;
}

//---------------- seqlock ----------------

// Writer side. The writer keeps its own counter, so a caller that overwrites the whole block
// (including `seq`) cannot break the sequence. Begin returns the counter to pass to End.
template <class Block>
uint64_t SeqlockBegin(Block* block) {
  std::atomic_ref<uint64_t> seq(block->seq);
  const uint64_t even = (seq.load(std::memory_order_relaxed) + 1) & ~uint64_t{1};
  seq.store(even + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  return even + 1;
}

template <class Block>
void SeqlockEnd(Block* block, uint64_t odd) {
  std::atomic_ref<uint64_t>(block->seq).store(odd + 1, std::memory_order_release);
}

enum class CopyResult { kOk, kWriterGone, kTimeout };

// Reader side: copies `*src` into `*dst` with `copy(src, dst)` (the whole block, or only the
// parts in use), retrying while the writer is inside its write. A writer that stays inside
// (it died there, or is stopped) is checked every few thousand retries: its pid (`writer_pid`,
// skipped when 0) and the caller's deadline `until_ns`.
template <class Block, class Copy>
CopyResult SeqlockCopy(Block* src, Block* dst, const Copy& copy, pid_t writer_pid,
                       int64_t until_ns) {
  static_assert(std::is_trivially_copyable_v<Block>);
  std::atomic_ref<uint64_t> seq(src->seq);
  for (uint32_t attempt = 1;; ++attempt) {
    const uint64_t before = seq.load(std::memory_order_acquire);
    if ((before & 1u) == 0) {
      copy(src, dst);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq.load(std::memory_order_relaxed) == before) {
        dst->seq = before;
        return CopyResult::kOk;
      }
    }
    if (attempt % 4096 == 0) {
      if (writer_pid != 0 && !ProcessAlive(writer_pid)) return CopyResult::kWriterGone;
      if (MonotonicNs() >= until_ns) return CopyResult::kTimeout;
      sched_yield();
    }
  }
}

//---------------- partial copies ----------------

// Copies `n` elements of the array member at `offset` (a byte offset into Block).
template <class Element, class Block>
inline void CopyElements(const Block* src, Block* dst, std::size_t offset, int n) {
  std::memcpy(reinterpret_cast<char*>(dst) + offset, reinterpret_cast<const char*>(src) + offset,
              sizeof(Element) * static_cast<std::size_t>(n));
}

// the command block up to its first `njoint` joints (njoint read from the block, clamped); the
// guard record lies before the joints and is copied with the head
inline void CopyCommands(const CommandBlock* src, CommandBlock* dst) {
  constexpr std::size_t kHead = offsetof(CommandBlock, joint);
  std::memcpy(static_cast<void*>(dst), static_cast<const void*>(src), kHead);
  const int n = dst->njoint < 0 ? 0 : dst->njoint > kMaxJoints ? kMaxJoints : dst->njoint;
  CopyElements<JointCommand>(src, dst, kHead, n);
}

// the sensor block's scalars and the first `counts.njoint`/`nforce`/`nimu` entries of its
// arrays (counts already clamped to the capacities)
inline void CopySensors(const SensorBlock* src, SensorBlock* dst, const SegmentHeader& counts) {
  constexpr std::size_t kHead = offsetof(SensorBlock, rejected_per_joint);
  std::memcpy(static_cast<void*>(dst), static_cast<const void*>(src), kHead);
  const int nj = counts.njoint;
  CopyElements<uint32_t>(src, dst, offsetof(SensorBlock, rejected_per_joint), nj);
  CopyElements<double>(src, dst, offsetof(SensorBlock, q), nj);
  CopyElements<double>(src, dst, offsetof(SensorBlock, dq), nj);
  CopyElements<double>(src, dst, offsetof(SensorBlock, tau), nj);
  CopyElements<ForceTorque>(src, dst, offsetof(SensorBlock, force), counts.nforce);
  CopyElements<Imu>(src, dst, offsetof(SensorBlock, imu), counts.nimu);
  dst->sim_truth = src->sim_truth;
  CopyElements<double>(src, dst, offsetof(SensorBlock, passive_q), counts.npassive);
  CopyElements<double>(src, dst, offsetof(SensorBlock, passive_dq), counts.npassive);
}

}  // namespace ohrp::shm::internal
