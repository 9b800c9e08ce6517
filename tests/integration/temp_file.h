// A helper of the runner's tests: small files (scenarios, logs) and folders written to /tmp.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace ohrp::runner {

// Writes `text` to a fresh file /tmp/ohrp_runner_test_<pid>_<n><suffix> and returns its path.
inline std::string Temp(const std::string& text, const char* suffix = ".yaml") {
  static int n = 0;
  const std::string p = "/tmp/ohrp_runner_test_" + std::to_string(getpid()) + "_" +
                        std::to_string(n++) + suffix;
  std::ofstream(p) << text;
  return p;
}

// Creates a fresh empty folder /tmp/ohrp_runner_test_<pid>_<n>.d (a run's output folder) and
// returns its path.
inline std::string TempDir() {
  const std::string p = Temp("", ".d");
  std::filesystem::remove(p);
  std::filesystem::create_directory(p);
  return p;
}

}  // namespace ohrp::runner
