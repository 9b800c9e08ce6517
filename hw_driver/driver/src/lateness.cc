// Wake-up lateness histogram (see lateness.h).
#include "hw_driver/lateness.h"

#include <algorithm>
#include <bit>

namespace ohrp::hw {

int LatenessHistogram::BinOf(int64_t ns) {
  if (ns < kSub) return ns < 0 ? 0 : static_cast<int>(ns);
  const uint64_t v = static_cast<uint64_t>(ns);
  const int e = 63 - std::countl_zero(v);  // v in [2^e, 2^(e+1)), e >= kSubBits
  const int octave = e - kSubBits;
  if (octave >= kOctaves) return kBins - 1;
  const int mantissa = static_cast<int>(v >> octave) - kSub;  // 0..kSub-1
  return kSub + octave * kSub + mantissa;
}

int64_t LatenessHistogram::BinLow(int i) {
  if (i < kSub) return i;
  const int octave = (i - kSub) / kSub;
  const int mantissa = (i - kSub) % kSub;
  return static_cast<int64_t>(kSub + mantissa) << octave;
}

void LatenessHistogram::Add(int64_t ns) noexcept {
  if (ns < 0) ns = 0;
  auto& bin = bins_[BinOf(ns)];
  bin.store(bin.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  count_.store(count_.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  sum_.store(sum_.load(std::memory_order_relaxed) + ns, std::memory_order_relaxed);
  if (ns > max_.load(std::memory_order_relaxed)) max_.store(ns, std::memory_order_relaxed);
}

void LatenessHistogram::Merge(const LatenessHistogram& other) {
  for (int i = 0; i < kBins; ++i) {
    bins_[i].fetch_add(other.bins_[i].load(std::memory_order_relaxed), std::memory_order_relaxed);
  }
  count_.fetch_add(other.count(), std::memory_order_relaxed);
  sum_.fetch_add(other.sum_.load(std::memory_order_relaxed), std::memory_order_relaxed);
  if (other.max_ns() > max_ns()) max_.store(other.max_ns(), std::memory_order_relaxed);
}

void LatenessHistogram::Reset() {
  for (auto& b : bins_) b.store(0, std::memory_order_relaxed);
  count_.store(0, std::memory_order_relaxed);
  sum_.store(0, std::memory_order_relaxed);
  max_.store(0, std::memory_order_relaxed);
}

double LatenessHistogram::mean_ns() const {
  const uint64_t n = count();
  return n == 0 ? 0.0 : static_cast<double>(sum_.load(std::memory_order_relaxed)) / n;
}

double LatenessHistogram::Percentile(double p) const {
  uint64_t total = 0;
  for (const auto& b : bins_) total += b.load(std::memory_order_relaxed);
  if (total == 0) return 0.0;
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * static_cast<double>(total);
  double below = 0;
  for (int i = 0; i < kBins; ++i) {
    const double n = static_cast<double>(bins_[i].load(std::memory_order_relaxed));
    if (n == 0) continue;
    if (below + n >= rank) {
      const double lo = static_cast<double>(BinLow(i));
      const double width = static_cast<double>(BinHigh(i) - BinLow(i));
      const double v = lo + width * std::clamp((rank - below) / n, 0.0, 1.0);
      return std::min(v, static_cast<double>(max_ns()));
    }
    below += n;
  }
  return static_cast<double>(max_ns());
}

std::vector<LatenessHistogram::Bin> LatenessHistogram::Octaves() const {
  std::vector<Bin> out;
  // the 1 ns bins below kSub go into one row
  uint64_t small = 0;
  for (int i = 0; i < kSub; ++i) small += bins_[i].load(std::memory_order_relaxed);
  if (small > 0) out.push_back({0, kSub, small});
  for (int o = 0; o < kOctaves; ++o) {
    uint64_t n = 0;
    for (int m = 0; m < kSub; ++m) n += bins_[kSub + o * kSub + m].load(std::memory_order_relaxed);
    if (n > 0) out.push_back({BinLow(kSub + o * kSub), BinLow(kSub + (o + 1) * kSub), n});
  }
  return out;
}

}  // namespace ohrp::hw
