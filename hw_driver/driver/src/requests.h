// What the loop reads of the stop requests (requests.cc; RequestStop and RequestEmergencyStop
// in driver.h set them).
#pragma once

namespace ohrp::hw {

int StopRequests() noexcept;              // how many stops were asked for so far
bool EmergencyStopRequested() noexcept;   // an emergency stop was asked for

}  // namespace ohrp::hw
