// Attaching to a robot segment by name, shared by both readers of a segment: the robot adaptor
// (the controller, read-write) and the observer (read-only). Maps the object, gives a producer
// still creating it a moment, and checks the file's owner, identity, layout, the producer's
// life and state, and the header's values.
#pragma once

#include <boost/interprocess/mapped_region.hpp>
#include <memory>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

// On success `*region` maps the whole Segment (read-write or read-only), `*checked` is the
// copy of its header that passed CheckHeaderValues (not yet sanitized) and `*fd` a descriptor
// of the segment's file (close-on-exec, for the per-cycle fstat; the caller closes it). On
// failure nothing stays mapped or open and the Status says which check failed and what to do.
// A file of another user than the effective uid is refused (kForeignOwner) unless
// `allow_other_owner` or the environment variable kAllowForeignSegmentEnv is "1".
Status AttachSegment(const std::string& segment_name, bool writable, bool allow_other_owner,
                     std::unique_ptr<boost::interprocess::mapped_region>* region,
                     SegmentHeader* checked, int* fd);

}  // namespace ohrp::shm::internal
