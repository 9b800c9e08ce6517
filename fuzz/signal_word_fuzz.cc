// Fuzzes the handshake's wake-up words (shm_bridge/src/signal_word.h) against a peer that
// scribbles on them: the input is a sequence of operations on one word in this process's
// memory: write 4 arbitrary bytes into it, post, or wait with a short deadline and an arbitrary
// learnt wait time. A corrupted word must be reported by both calls and left as found; a valid
// one must behave as the protocol says (layout.h); no wait may outlast its deadline by much.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "signal_word.h"
#include "sync.h"

namespace shm = ohrp::shm;
namespace in = ohrp::shm::internal;

namespace {

constexpr int64_t kSlackNs = 50000000;  // a wait may end this much after its deadline [ns]

// the next `n` input bytes as a little-endian number (zeros past the end)
uint64_t Take(const uint8_t*& data, size_t& size, size_t n) {
  uint64_t v = 0;
  for (size_t i = 0; i < n; ++i) {
    if (size > 0) {
      v |= static_cast<uint64_t>(*data) << (8 * i);
      ++data;
      --size;
    }
  }
  return v;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  shm::SignalWord s{0, -1, 0};
  std::atomic_ref<uint32_t> word(s.word);
  while (size > 0) {
    const uint32_t before = word.load();
    switch (Take(data, size, 1) % 3) {
      case 0:  // a scribbler writes the word
        word.store(static_cast<uint32_t>(Take(data, size, 4)));
        break;
      case 1: {  // a post
        const bool posted = in::Post(&s);
        if (posted != in::ValidSignalWord(before)) std::abort();
        if (word.load() != (before | shm::kSignalPosted)) std::abort();
        break;
      }
      default: {  // a wait of at most 20 us, its spin learnt from an arbitrary past
        int64_t typical = static_cast<int64_t>(Take(data, size, 4)) - 1000;
        if (in::SpinBudget(typical) < 0 || in::SpinBudget(typical) > in::kMaxSpinNs) std::abort();
        const int64_t start = ohrp::MonotonicNs();
        const int64_t until = start + static_cast<int64_t>(Take(data, size, 1)) * 80;
        const in::SignalResult r = in::Wait(&s, until, &typical);
        if (ohrp::MonotonicNs() > until + kSlackNs) std::abort();
        if (!in::ValidSignalWord(before)) {
          if (r != in::SignalResult::kCorrupt || word.load() != before) std::abort();
        } else if ((before & shm::kSignalPosted) != 0) {
          if (r != in::SignalResult::kSignalled || word.load() != 0) std::abort();
        } else if (r != in::SignalResult::kTimeout || word.load() != 0) {
          std::abort();  // nobody posts here: a timeout, the sleeping bit cleared again
        }
        break;
      }
    }
  }
  return 0;
}
