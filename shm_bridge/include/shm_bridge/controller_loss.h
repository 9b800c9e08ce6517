// What a producer (sim_host, hw_driver) does when it loses its controller, and how a lost
// controller is let go. One policy and one option text for both producers:
//   --on-controller-loss end | wait | continue
//
// A controller is lost when its process dies, when it detaches (closes its adaptor) or when it
// does not answer within the producer's timeout (sim_host: --controller-timeout in lock-step;
// hw_driver: --watchdog-cycles). A silent controller is still alive and still holds the
// segment's controller slot: the producer frees the slot (Producer::DropController), so that a
// new controller can attach, and so that the silent one, should it run again (resumed after a
// SIGSTOP, back from a long stall), learns on its next read or write that it was dropped
// (ReadResult::kDropped) instead of commanding a robot that has moved on without it.
#pragma once

#include <string>

namespace ohrp::shm {

enum class ControllerLoss {
  kEnd,       // end the run (the producer's "controller lost" exit code)
  kWait,      // hold the robot safely and wait for a new controller to attach
  kContinue,  // go on with the last references held (sim_host only)
};

// "end", "wait" or "continue".
const char* ControllerLossName(ControllerLoss loss);

// Reads "end", "wait" or "continue" into `*out`; false (and `*out` unchanged) for anything else.
bool ParseControllerLoss(const std::string& text, ControllerLoss* out);

}  // namespace ohrp::shm
