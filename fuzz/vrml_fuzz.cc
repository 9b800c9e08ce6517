// Fuzzes the VRML reader (vrml::ConvertText: tokens, PROTO/DEF/USE parsing, the kinematic tree,
// the MJCF writer; robot_model/src/vrml/): it must accept or refuse with a message that names
// the file, the line and the column; what it accepts is an MJCF document.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <regex>
#include <string>

#include "vrml/vrml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string mjcf, error;
  if (!ohrp::vrml::ConvertText(text, "fuzz.wrl", &mjcf, &error)) {
    static const std::regex kWhere("^fuzz\\.wrl:[0-9]+:[0-9]+: .+");
    if (!std::regex_search(error, kWhere)) std::abort();
    return 0;
  }
  if (mjcf.rfind("<mujoco model=\"", 0) != 0 || mjcf.find("</mujoco>\n") == std::string::npos)
    std::abort();
  return 0;
}
