// The exported entry of libohrp_io_udp.so (see hw_driver/robot_io.h, kRobotIoEntry).
#include <new>

#include "hw_udp/udp_io.h"

extern "C" ohrp::hw::RobotIo* ohrp_create_robot_io(uint32_t abi_version) {
  if (abi_version != ohrp::hw::kRobotIoAbiVersion) return nullptr;
  return new (std::nothrow) ohrp::hw::udp::UdpIo();
}
