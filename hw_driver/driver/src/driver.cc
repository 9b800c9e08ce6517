// The driver (see driver.h): its construction and its run. The loop's cycle is driver_loop.cc,
// its holds and safety checks driver_safety.cc, its state driver_state.h; the names of states
// and events names.cc; the stop requests requests.cc.
#include "hw_driver/driver.h"

#include "driver_loop.h"

namespace ohrp::hw {

Driver::Driver(const DriverOptions& options, const shm::ProducerConfig& robot, RobotIo* io,
               shm::Producer* producer)
    : impl_(new Impl(options, robot, io, producer)) {}

Driver::~Driver() { delete impl_; }

void Driver::SetLog(datalog::Recorder* log) { impl_->log = log; }

const rt::RtReport& Driver::PrepareRealTime() {
  if (!rt_prepared_) {
    rt_ = rt::SetUpRealTime(impl_->opt.rt);
    rt_prepared_ = true;
  }
  return rt_;
}

//---------------- the loop (driver_loop.h) ----------------

int Driver::Run() {
  result_ = DriverResult{};
  result_.rt = PrepareRealTime();
  DriverLoop loop(*impl_, result_, live_);
  while (loop.Cycle()) {
  }
  loop.Finish();
  return result_.exit_code;
}

}  // namespace ohrp::hw
