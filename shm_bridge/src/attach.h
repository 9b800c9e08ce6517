// Attaching to a robot segment by name, shared by both readers of a segment: the robot adaptor
// (the controller, read-write) and the observer (read-only). Maps the object, gives a producer
// still writing its header a moment, and checks identity, layout, the producer's life and
// state, and the header's values.
#pragma once

#include <boost/interprocess/mapped_region.hpp>
#include <memory>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

// On success `*region` maps the whole Segment (read-write or read-only) and `*checked` is the
// copy of its header that passed CheckHeaderValues (not yet sanitized). On failure nothing
// stays mapped and the Status says which check failed and what to do.
Status AttachSegment(const std::string& segment_name, bool writable,
                     std::unique_ptr<boost::interprocess::mapped_region>* region,
                     SegmentHeader* checked);

}  // namespace ohrp::shm::internal
