// Fuzzes the pose file reader (controllers: ParsePose, then ResolvePose onto a few joints): it
// must accept or refuse with a message, and what it accepts holds finite values, once per joint.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "controllers/pose.h"

namespace ctl = ohrp::controllers;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ctl::Pose pose;
  const ctl::ConfigStatus status = ctl::ParsePose(text, "fuzz.yaml", &pose);
  if (!status.ok()) {
    if (status.message.empty()) std::abort();
    return 0;
  }
  // every joint named once, with a finite value
  std::set<std::string> names;
  for (const ctl::PoseEntry& entry : pose.joints) {
    if (!std::isfinite(entry.value) || !names.insert(entry.joint).second) std::abort();
  }
  // mapped onto a robot: its joints in order, the others refused with a message
  const std::vector<std::string> robot = {"RLEG_HIP_P", "RLEG_KNEE", "WAIST_Y"};
  std::vector<double> q;
  const ctl::ConfigStatus resolved = ctl::ResolvePose(pose, robot, &q);
  if (resolved.ok() ? q.size() != robot.size() : resolved.message.empty()) std::abort();
  return 0;
}
