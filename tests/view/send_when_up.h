// A line to a program's local control socket from a test, once the program is up.
#pragma once

#include <chrono>
#include <string>
#include <thread>

#include "view/control.h"

namespace ohrp::view::testing {

// `line` to the program listening on local socket `path`, retried while the socket is not up yet
// (10 s at most); the program's reply, or SendLine's error
inline std::string SendWhenUp(const std::string& path, const std::string& line) {
  std::string reply;
  for (int i = 0; i < 200; ++i) {
    if (SendLine(path, line, 60.0, &reply) || reply.rfind("cannot connect", 0) != 0) return reply;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return reply;
}

}  // namespace ohrp::view::testing
