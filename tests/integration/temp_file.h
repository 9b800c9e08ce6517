// A helper of the runner's tests: small files (scenarios, logs) and run output folders, in the
// test process's scratch folder (common/scratch.h), removed when the test ends.
#pragma once

#include <string>

#include "common/scratch.h"

namespace ohrp::runner {

// Writes `text` to a fresh file in the scratch folder and returns its path.
inline std::string Temp(const std::string& text, const char* suffix = ".yaml") {
  return ohrp::testing::ScratchFile("runner_test", text, suffix);
}

// Creates a fresh empty folder in the scratch folder (a run's output folder) and returns its
// path.
inline std::string TempDir() { return ohrp::testing::ScratchFolder("runner_test"); }

}  // namespace ohrp::runner
