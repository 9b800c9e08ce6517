// Loading a RobotIo implementation from a shared object at start-up (robot_io.h): dlopen, look
// up kRobotIoEntry, create the boards' object with the driver's ABI version.
#pragma once

#include <memory>
#include <string>

#include "hw_driver/robot_io.h"

namespace ohrp::hw {

// A loaded plugin: the library handle and the RobotIo it created. The RobotIo is destroyed
// before the library is unloaded.
class IoPlugin {
 public:
  // Loads `path` (a file path; a name without '/' is looked up as dlopen does). On failure
  // returns null and sets `*error` to a sentence naming the file and the reason (dlerror's
  // text, a missing entry symbol, or an ABI version the plugin refused).
  static std::unique_ptr<IoPlugin> Load(const std::string& path, std::string* error);
  ~IoPlugin();
  IoPlugin(const IoPlugin&) = delete;
  IoPlugin& operator=(const IoPlugin&) = delete;

  RobotIo& io() { return *io_; }
  const std::string& path() const { return path_; }

 private:
  IoPlugin() = default;
  void* handle_ = nullptr;
  RobotIo* io_ = nullptr;
  std::string path_;
};

}  // namespace ohrp::hw
