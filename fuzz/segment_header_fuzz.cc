// Fuzzes the checks a controller runs on a segment header when it attaches (shm_bridge:
// CheckHeader, CheckHeaderValues, SanitizedHeader), in the order Adaptor::Attach runs them. The
// input's bytes are the header (short inputs are zero-padded). The identity fields are then
// stamped with this build's layout so that most inputs reach the value checks.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "shm_bridge/checks.h"

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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  shm::SegmentHeader h;
  std::memset(&h, 0, sizeof(h));
  std::memcpy(&h, data, size < sizeof(h) ? size : sizeof(h));

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
