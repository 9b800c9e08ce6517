// Fuzzes the runner's scenario parser (tools/runner: ParseScenario) with arbitrary text: it must
// accept or refuse with a message, never crash, and what it accepts must be within its bounds.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "runner/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ohrp::runner::Scenario scenario;
  std::string error;
  // a refusal must say why
  if (!ohrp::runner::ParseScenario(text, "fuzz.yaml", &scenario, &error)) {
    if (error.empty()) std::abort();
    return 0;
  }
  // an accepted run has a step (0: the scene's), a period (0: sim_host's, the multiple of the
  // step nearest 5 ms) and a duration within their bounds and checks to make
  if (!(scenario.physics_dt >= 0 && scenario.physics_dt <= 0.1) ||
      !(scenario.control_period >= 0 && scenario.control_period <= 1) ||
      !(scenario.duration >= scenario.control_period && scenario.duration <= 1e5) ||
      scenario.checks.empty()) {
    std::abort();
  }
  return 0;
}
