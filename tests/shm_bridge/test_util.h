// Helpers for the shm_bridge tests: unique segment names, a small producer config, and the
// forked children with exit codes and the pipes for ordering steps across processes
// (common/process.h).
#pragma once

#include <unistd.h>

#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <functional>
#include <string>

#include "common/process.h"
#include "shm_bridge/bridge.h"
#include "shm_bridge/clock.h"  // MonotonicSeconds: system-wide, comparable across processes

namespace ohrp::shm::testing {

using ohrp::testing::Pipe;
using ohrp::testing::Spawn;
using ohrp::testing::WaitExit;

// a segment name unique to this test process and `tag`
inline std::string UniqueSegment(const std::string& tag) {
  return "test_" + tag + "_" + std::to_string(getpid());
}

inline void RemoveSegment(const std::string& segment_name) {
  boost::interprocess::shared_memory_object::remove(SegmentObjectName(segment_name).c_str());
}

inline std::string DevShmPath(const std::string& segment_name) {
  return "/dev/shm/" + SegmentObjectName(segment_name);
}

// a valid three-joint configuration
inline ProducerConfig SmallConfig(const std::string& segment_name) {
  ProducerConfig c;
  c.segment_name = segment_name;
  c.kind = ProducerKind::kSimulation;
  c.robot_name = "testbot";
  c.joint_names = {"hip", "knee", "ankle"};
  c.force_names = {"foot_ft"};
  c.imu_names = {"base_imu"};
  c.q_min = {-1.0, -2.0, -0.5};
  c.q_max = {1.0, 0.0, 0.5};
  c.tau_max = {100.0, 80.0, 40.0};
  c.default_kp = {300.0, 200.0, 100.0};
  c.default_kd = {3.0, 2.0, 1.0};
  c.physics_period = 0.001;
  c.control_period = 0.005;
  c.read_timeout_hint = 1.0;
  return c;
}

// Polls `condition` every millisecond until it holds or `timeout` [s] passes.
inline bool WaitFor(const std::function<bool()>& condition, double timeout = 5.0) {
  const double deadline = MonotonicSeconds() + timeout;
  while (!condition()) {
    if (MonotonicSeconds() > deadline) return false;
    usleep(1000);
  }
  return true;
}

// Opens `segment_name` as a controller, retrying while the producer is not there yet.
inline Status OpenWhenReady(RobotAdaptor* adaptor, const std::string& segment_name,
                            const AdaptorOptions& options = {}, double timeout = 5.0) {
  const double deadline = MonotonicSeconds() + timeout;
  for (;;) {
    Status s = adaptor->open(segment_name, options);
    if (s.code != Error::kNoSegment || MonotonicSeconds() > deadline) return s;
    usleep(1000);
  }
}

// Maps the whole object of `segment_name` read-write, to corrupt fields on purpose.
class RawSegment {
 public:
  explicit RawSegment(const std::string& segment_name)
      : shm_(boost::interprocess::open_only, SegmentObjectName(segment_name).c_str(),
             boost::interprocess::read_write),
        region_(shm_, boost::interprocess::read_write) {}
  Segment* get() { return static_cast<Segment*>(region_.get_address()); }

 private:
  boost::interprocess::shared_memory_object shm_;
  boost::interprocess::mapped_region region_;
};

}  // namespace ohrp::shm::testing
