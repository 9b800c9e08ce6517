// Fuzzes the checks a controller runs on a segment header when it attaches (shm_bridge:
// CheckHeader, CheckHeaderValues, SanitizedHeader), in the order Adaptor::Attach runs them, and
// the check both ends run on a mapped segment once a cycle (LookAtSegment, src/segment_guard.h).
// The input's bytes are the header (short inputs are zero-padded), then optionally the object's
// size (8 bytes: a truncated file), the two wake-up words (4 bytes each: a scribbler's values)
// and the producer pid the checking end expects (4 bytes). For the value checks the identity
// fields are then stamped with this build's layout so that most inputs reach them.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "segment_guard.h"
#include "shm_bridge/checks.h"
#include "signal_word.h"

namespace shm = ohrp::shm;

namespace {

// a header the value checks accepted must be safe to use as Attach uses it
void CheckAccepted(const shm::SegmentHeader& checked) {
  const shm::SegmentHeader h = shm::SanitizedHeader(checked);
  if (h.njoint != checked.njoint || h.nforce != checked.nforce || h.nimu != checked.nimu ||
      h.ncamera != checked.ncamera) {
    std::abort();  // the values check let a count outside its capacity through
  }
  for (int j = 0; j < h.njoint; ++j) {
    if (std::isnan(h.q_min[j]) || std::isnan(h.q_max[j]) || !(h.q_min[j] <= h.q_max[j]) ||
        !(h.tau_max[j] >= 0) || !std::isfinite(h.default_kp[j]) || h.default_kp[j] < 0 ||
        !std::isfinite(h.default_kd[j]) || h.default_kd[j] < 0) {
      std::abort();
    }
  }
  if (!(h.control_period > 0) || !std::isfinite(h.control_period) || !(h.physics_period >= 0) ||
      h.physics_period > h.control_period || !(h.read_timeout_hint > 0)) {
    std::abort();
  }
}

// the per-cycle look at a segment whose header (as another process left it), wake-up words and
// expected producer pid come from the input: it must find exactly what segment_guard.h says
void CheckLook(const shm::SegmentHeader& h, const uint8_t* rest, size_t rest_size) {
  static shm::Segment* segment = new shm::Segment();  // 17 MB once: zeros beyond the header
  uint32_t words[2] = {0, 0};
  int32_t expected = h.producer_pid;
  if (rest_size >= sizeof(words)) std::memcpy(words, rest, sizeof(words));
  if (rest_size >= sizeof(words) + sizeof(expected)) {
    std::memcpy(&expected, rest + sizeof(words), sizeof(expected));
  }
  segment->header = h;
  segment->sync.sensors_ready.word = words[0];
  segment->sync.commands_ready.word = words[1];
  const shm::SegmentFault seen = shm::internal::LookAtSegment(*segment, expected);
  const bool words_ok = shm::internal::ValidSignalWord(words[0]) &&
                        shm::internal::ValidSignalWord(words[1]);
  const bool state_ok = h.state >= static_cast<uint32_t>(shm::ProducerState::kRunning) &&
                        h.state <= static_cast<uint32_t>(shm::ProducerState::kFailed);
  const bool header_ok = std::memcmp(h.magic, shm::kMagic, sizeof(h.magic)) == 0 &&
                         h.producer_pid == expected && state_ok;
  const shm::SegmentFault want = !words_ok    ? shm::SegmentFault::kWakeUpWords
                                 : !header_ok ? shm::SegmentFault::kHeader
                                              : shm::SegmentFault::kNone;
  if (seen != want) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  shm::SegmentHeader h;
  std::memset(&h, 0, sizeof(h));
  std::memcpy(&h, data, size < sizeof(h) ? size : sizeof(h));
  const size_t tail = sizeof(h) + sizeof(uint64_t);  // the words and pid after the size
  CheckLook(h, data + (size > tail ? tail : size), size > tail ? size - tail : 0);

  // the identity check on the bytes as they are (the object's size from the input too); bytes
  // that fail it get this build's identity, so that they reach the value checks
  uint64_t object_size = sizeof(shm::Segment);
  if (size >= sizeof(h) + sizeof(object_size)) {
    std::memcpy(&object_size, data + sizeof(h), sizeof(object_size));
  }
  if (!shm::CheckHeader(h, object_size, "fuzz").ok()) {
    std::memcpy(h.magic, shm::kMagic, sizeof(h.magic));
    h.layout_version = shm::kLayoutVersion;
    h.layout_hash = shm::LayoutHash();
    h.header_size = sizeof(shm::SegmentHeader);
    h.segment_size = sizeof(shm::Segment);
    if (!shm::CheckHeader(h, sizeof(shm::Segment), "fuzz").ok()) std::abort();
  }
  const shm::Status values = shm::CheckHeaderValues(h, "fuzz");
  if (values.ok()) CheckAccepted(h);
  return 0;
}
