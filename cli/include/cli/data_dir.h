// Where a program finds the project's data (mjcf/, scenarios/, controllers/poses/, the viewer's
// web page, the plot scripts): one answer for every program and library, nothing compiled in.
//
//   $OHRP_DATA_DIR, when set and not empty (e.g. a sweep node with the data elsewhere);
//   else <folder of the running program>/../share/ohrp:
//     installed:   <prefix>/bin/sim_host         -> <prefix>/share/ohrp (cmake --install, the .deb)
//     build tree:  build/bin/sim_host, build/tests/x_test -> build/share/ohrp, whose entries
//                  cmake links to the checkout's folders at configure time (cmake/OhrpData.cmake)
//
// The folders inside keep the checkout's relative paths, so a scenario's "mjcf/hrp1s/hrp1s.xml"
// or "controllers/poses/x.yaml" resolves against DataDir() wherever the programs are.
//
// Use:
//   std::string model = ohrp::cli::DataPath("mjcf/hrp1s/hrp1s.xml");
//
// Header-only and without CLI11, so that the libraries (controllers, balance) can use it too.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

namespace ohrp::cli {

// The folder of the running executable ("" if /proc/self/exe cannot be read).
inline std::string ProgramDir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::canonical("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

// The data root (see the top of this file); without a trailing slash, symbolic links resolved.
inline std::string DataDir() {
  if (const char* env = std::getenv("OHRP_DATA_DIR"); env != nullptr && env[0] != '\0') {
    return env;
  }
  const std::string bin = ProgramDir();
  // the links resolved: "<prefix>/bin/../share/ohrp" -> "<prefix>/share/ohrp", and in the build
  // tree the checkout itself, so that a path joined to it and normalized lexically (a scenario's
  // "../shared/..." beside the checkout) is the file the system would open
  const std::filesystem::path dir =
      std::filesystem::path(bin.empty() ? "." : bin) / ".." / "share" / "ohrp";
  std::error_code ec;
  const std::filesystem::path resolved = std::filesystem::weakly_canonical(dir, ec);
  return (ec ? dir.lexically_normal() : resolved).string();
}

// `relative` (a path inside the data root, e.g. "mjcf/hrp1s/hrp1s.xml") as a full path.
inline std::string DataPath(std::string_view relative) {
  return DataDir() + "/" + std::string(relative);
}

}  // namespace ohrp::cli
