// Fuzzes the footstep file readers (walking: ParseFootstepText, as YAML and as CSV, from a stance
// of HRP-1S's width): it must accept or refuse with a message that names the file, and what it
// accepts is a non-empty list of finite steps that keeps the limits from the stance.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "walking/footstep_file.h"

namespace wk = ohrp::walking;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  wk::StepLimits limits;
  limits.width = 0.18;
  wk::FeetPose start;
  start.p[wk::kLeft] = Eigen::Vector3d(0.055, 0.09, 0);
  start.p[wk::kRight] = Eigen::Vector3d(0.055, -0.09, 0);
  start.yaw[wk::kLeft] = start.yaw[wk::kRight] = 0;
  for (const auto format : {wk::FootstepFormat::kYaml, wk::FootstepFormat::kCsv}) {
    const std::string name = format == wk::FootstepFormat::kYaml ? "fuzz.yaml" : "fuzz.csv";
    std::vector<wk::Footstep> steps;
    std::string error;
    if (!wk::ParseFootstepText(text, format, name, start, limits, &steps, &error)) {
      if (error.rfind(name + ":", 0) != 0 || !steps.empty()) std::abort();
      continue;
    }
    // accepted: finite steps within the limits
    if (steps.empty() || !wk::CheckSteps(start, steps, limits).empty()) std::abort();
  }
  return 0;
}
