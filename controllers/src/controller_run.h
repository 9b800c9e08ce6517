// RunController's stages (runner.h): one run of a controller against a segment, as an object
// with one method per stage, the way the cycle reads:
//   Attach     the segment, retried until --attach-timeout
//   Configure  the controller for the segment's robot, the self-collision guard, the images it
//              wants, the fall watch, real-time scheduling; then the start line
//   Loop       read, activate once, images, update, guard, fall watch, write: no allocation,
//              throwing or logging
//   End        release the segment, judge why the run ended (the producer's verdict, a fall, a
//              signal), the controller's and the guard's verdicts, the counters
// runner.cc runs them in order; a stage that ends the run has set the report's exit code.
#pragma once

#include <array>
#include <memory>
#include <ostream>
#include <string>

#include "controllers/runner.h"
#include "controllers/self_collision_guard.h"
#include "shm_bridge/bridge.h"

namespace ohrp::controllers {

// true once SIGINT/SIGTERM or RequestStop asked the running controller to stop (runner.cc)
bool StopRequested() noexcept;

class ControllerRun {
 public:
  ControllerRun(Controller& controller, const RunOptions& options, std::ostream& out,
                std::ostream& err, RunReport* report);
  ControllerRun(const ControllerRun&) = delete;
  ControllerRun& operator=(const ControllerRun&) = delete;

  bool Attach();     // false: the run is over before it began
  bool Configure();  // false: the robot, the guard's file or the images do not fit
  void Loop();
  void End();

  ExitCode exit_code() const { return rep_.exit_code; }

 private:
  // Configure's parts
  bool ConfigureGuard();
  bool RequestImages();
  void ConfigureFallWatch();
  void SetUpRealTime();
  bool Refuse(ExitCode code);  // closes the adaptor and the controller: the run never started
  // Loop's parts
  bool Cycle();  // one control cycle; false ends the loop
  void ReadImages();
  // End's parts
  void Release();
  std::string WhyItEnded();
  std::string EndOfProducerRun();
  void JudgeController();
  std::string GuardFailure() const;
  void ReportCounters();

  Controller& controller_;
  const RunOptions& options_;
  std::ostream& out_;
  std::ostream& err_;
  RunReport local_;
  RunReport& rep_;
  const std::string& prog_;
  const std::string seg_;  // the segment's name, quoted for messages
  std::string producer_;   // "sim_host (pid N)"

  shm::RobotAdaptor adaptor_;
  SelfCollisionGuard guard_;
  bool guarded_ = false;
  FallWatch watch_;
  uint32_t cameras_ = 0;
  std::unique_ptr<shm::ImageSlot> image_;
  std::array<uint64_t, shm::kMaxCameras> last_frame_{};

  // the loop's state
  shm::SensorBlock sensors_{};
  shm::CommandBlock commands_{};
  shm::ReadResult result_ = shm::ReadResult::kOk;
  bool stopped_by_signal_ = false, fell_ = false, active_ = false, producer_failed_ = false;
  uint32_t last_status_ = 0;
  uint64_t late_ = 0, rejected_ = 0;
};

}  // namespace ohrp::controllers
