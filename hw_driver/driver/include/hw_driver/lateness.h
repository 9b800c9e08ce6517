// The wake-up lateness histogram of a periodic loop: how long after its absolute deadline the
// loop actually woke up. Log-scaled bins (32 per octave, about 3 % wide) from 1 ns to about
// 18 minutes, so percentiles are read to a few per cent whatever the scale.
//
// One writer (the loop) and any number of readers (a reporter thread, the end-of-run report):
// every counter is a std::atomic accessed with relaxed loads and stores, so Add never takes a
// lock, never allocates and never blocks. A reader sees each bin exactly, the totals possibly
// one sample apart.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

namespace ohrp::hw {

class LatenessHistogram {
 public:
  static constexpr int kSubBits = 5;                     // 2^5 = 32 bins per octave
  static constexpr int kSub = 1 << kSubBits;
  static constexpr int kOctaves = 36;                    // up to 2^41 ns
  static constexpr int kBins = kSub + kOctaves * kSub;   // the first kSub bins are 1 ns wide

  // Records one lateness [ns]; negative values count as 0. Real-time safe (single writer).
  void Add(int64_t ns) noexcept;
  // Adds every bin of `other` (not real-time safe: meant for the end of a run).
  void Merge(const LatenessHistogram& other);
  void Reset();

  uint64_t count() const { return count_.load(std::memory_order_relaxed); }
  int64_t max_ns() const { return max_.load(std::memory_order_relaxed); }
  double mean_ns() const;
  // The p-th percentile (0..100) [ns], interpolated inside its bin and never above max_ns().
  // 0 when empty.
  double Percentile(double p) const;

  // The bounds [lo, hi) [ns] of bin `i`, and the bin of a value.
  static int64_t BinLow(int i);
  static int64_t BinHigh(int i) { return BinLow(i + 1); }
  static int BinOf(int64_t ns);

  struct Bin {
    int64_t lo_ns, hi_ns;
    uint64_t count;
  };
  // The bins holding samples, merged into octaves (factor-2 wide) for printing.
  std::vector<Bin> Octaves() const;

 private:
  std::array<std::atomic<uint64_t>, kBins> bins_{};
  std::atomic<uint64_t> count_{0};
  std::atomic<int64_t> max_{0};
  std::atomic<int64_t> sum_{0};  // [ns]
};

}  // namespace ohrp::hw
