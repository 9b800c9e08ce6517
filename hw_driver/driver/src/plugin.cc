// Plugin loading (see plugin.h).
#include "hw_driver/plugin.h"

#include <dlfcn.h>

namespace ohrp::hw {

std::unique_ptr<IoPlugin> IoPlugin::Load(const std::string& path, std::string* error) {
  dlerror();
  void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle == nullptr) {
    const char* why = dlerror();
    *error = "cannot load IO plugin '" + path + "': " + (why ? why : "unknown dlopen error");
    return nullptr;
  }
  using Entry = RobotIo* (*)(uint32_t);
  dlerror();
  void* symbol = dlsym(handle, kRobotIoEntry);
  if (symbol == nullptr) {
    const char* why = dlerror();
    *error = "IO plugin '" + path + "' does not export '" + kRobotIoEntry + "'" +
             (why ? std::string(": ") + why : std::string()) +
             " (is it built from hw_driver/robot_io.h?)";
    dlclose(handle);
    return nullptr;
  }
  RobotIo* io = reinterpret_cast<Entry>(symbol)(kRobotIoAbiVersion);
  if (io == nullptr) {
    *error = "IO plugin '" + path + "' refused the driver's ABI version " +
             std::to_string(kRobotIoAbiVersion) + "; rebuild it against this driver";
    dlclose(handle);
    return nullptr;
  }
  std::unique_ptr<IoPlugin> plugin(new IoPlugin());
  plugin->handle_ = handle;
  plugin->io_ = io;
  plugin->path_ = path;
  return plugin;
}

IoPlugin::~IoPlugin() {
  delete io_;
  io_ = nullptr;
  if (handle_ != nullptr) dlclose(handle_);
}

}  // namespace ohrp::hw
