// Validation shared by both ends of a robot segment (see layout.h and bridge.h): the checks a
// producer runs on its configuration before creating a segment, and the checks a controller
// runs on a header before trusting it. Exposed so tests and tools (e.g. a segment inspector)
// give the same answers and the same messages as the bridge itself.
#pragma once

#include <cstdint>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm {

// Checks `config` against the layout: segment name, counts <= capacities, every name non-empty
// (joints, sensors) and shorter than kNameLen, per-joint vectors empty or of njoint entries,
// finite limits with q_min <= q_max, tau_max >= 0, default gains finite and >= 0,
// control_period > 0, physics_period in [0, control_period] (0 for hardware),
// read_timeout_hint > 0; the model identity: link_mass and joint_axis empty or of njoint finite
// entries, masses >= 0, nbody >= 0. Returns kOk, or kInvalidConfig with a
// message that names the offending field (e.g. "joint_names[3]").
Status ValidateConfig(const ProducerConfig& config);

// Checks that `header`, read from an object of `object_size` bytes, describes a segment of
// this build's layout. Returns kNotASegment (object too small, wrong magic), kLayoutMismatch
// (layout_version, layout_hash, header_size or segment_size differ; the message gives both
// sides) or kOk. Does not look at the state or the pids. `segment_name` is only for messages.
Status CheckHeader(const SegmentHeader& header, uint64_t object_size,
                   const std::string& segment_name);

// Checks the values of a header that passed CheckHeader, before any of them is used: counts
// njoint, nforce, nimu, ncamera within [0, capacity]; per joint (njoint) q_min <= q_max (either
// may be infinite, neither NaN), tau_max >= 0, default_kp, default_kd and link_mass finite and
// >= 0, joint_axis finite; declared cameras with a size and fovy in (0, 180) deg;
// control_period finite and > 0, physics_period in [0, control_period], read_timeout_hint
// finite and > 0; nbody >= 0, total_mass finite and >= 0. Returns kOk, or kInvalidHeader with a
// message naming the first field that is wrong, its value and the rule. `segment_name` is only
// for messages.
Status CheckHeaderValues(const SegmentHeader& header, const std::string& segment_name);

// A copy of `header` that is safe to use: counts clamped to [0, capacity] and every name
// NUL-terminated. The shared fields `state` and `controller_pid` are copied as they are.
SegmentHeader SanitizedHeader(const SegmentHeader& header);

}  // namespace ohrp::shm
