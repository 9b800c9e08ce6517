// The controller lifecycle: one small state machine shared by every controller program.
//
//                 configure(header)              activate(first sensors)
//   kUnconfigured ----------------> kInactive -------------------------> kActive
//        |                           ^   |                                  |  update(sensors,
//        |                           |   |          deactivate()            |  commands) every
//        |                           |   +<---------------------------------+  cycle
//        |  close()                  |  close()
//        +-------------------------> kClosed <-- (terminal)
//
//   configure   set-up: match the controller's files and parameters to the robot described by
//               the segment header (joint names and count, limits, default gains). May
//               allocate and fail; a failure leaves the state kUnconfigured.
//   activate    called on the first sensor block: take the current pose as the starting point.
//               From here on commands are allowed. Does not allocate, throw or log.
//   update      every cycle: fill the command block from the sensor block. Does not allocate,
//               throw or log. After the controller's own update the commands are guarded:
//               non-finite values are replaced by a hold and positions are clamped to the
//               joint limits; both are counted (counters()), never printed per cycle.
//   deactivate  stop issuing commands (the producer holds the last ones). Back to kInactive.
//   close       release what configure took. Terminal.
// A call in the wrong state does nothing and returns false (or kState).
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <limits>
#include <string>
#include <vector>

#include "controllers/config_status.h"
#include "controllers/fall_watch.h"
#include "shm_bridge/layout.h"

namespace ohrp::controllers {

enum class LifecycleState { kUnconfigured, kInactive, kActive, kClosed };
const char* LifecycleStateName(LifecycleState s);

// problems counted in the per-cycle path, reported after the loop
struct CycleCounters {
  uint64_t updates = 0;            // update() calls that produced commands
  uint64_t non_finite_fixed = 0;   // joint commands whose non-finite values were replaced
  uint64_t clamped = 0;            // joint position references clamped to the joint limits
  uint64_t diverged_sensors = 0;   // sensor blocks flagged kDiverged by the producer
};

class Controller {
 public:
  virtual ~Controller() = default;
  Controller(const Controller&) = delete;
  Controller& operator=(const Controller&) = delete;

  // kUnconfigured -> kInactive. Keeps a copy of `header`; calls on_configure.
  ConfigStatus configure(const shm::SegmentHeader& header);
  // kInactive -> kActive. Records the first sensor block's positions as the hold pose.
  bool activate(const shm::SensorBlock& sensors) noexcept;
  // kActive only: fills `*commands` (njoint, modes, references, gains) and guards them.
  bool update(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept;
  // kActive -> kInactive.
  bool deactivate() noexcept;
  // kUnconfigured or kInactive -> kClosed.
  bool close();

  LifecycleState state() const { return state_; }
  const CycleCounters& counters() const { return counters_; }
  // the header given to configure (valid from kInactive on)
  const shm::SegmentHeader& header() const { return header_; }
  int njoint() const { return header_.njoint; }
  // the robot's joint names, joint-id order (valid from kInactive on)
  const std::vector<std::string>& joint_names() const { return joint_names_; }
  // What the controller has to say after the run (the runner calls it once, after close);
  // the default says nothing.
  virtual void report(std::ostream& out) const { (void)out; }

  // The fall watch (fall_watch.h), run by the runner on every sensor block. fall_limits: the
  // limits for this robot, called once after configure (the default keeps DefaultFallLimits; a
  // controller that knows its model narrows them). base_tilt: the controller's own estimate of
  // the base's tilt from upright [rad], NaN when it has none (the IMU's orientation is used).
  virtual void fall_limits(FallLimits* limits) const { (void)limits; }
  virtual double base_tilt() const noexcept { return kNoTilt; }
  // what base_tilt is measured from, for the fall's message: "upright" unless the controller
  // tilts the base on purpose (walk's rolling pelvis: its commanded orientation)
  virtual const char* tilt_reference() const noexcept { return "upright"; }
  // its estimate of the CoM's height over its lower sole [m], NaN when it has none
  virtual double com_height() const noexcept { return kNoTilt; }
  static constexpr double kNoTilt = std::numeric_limits<double>::quiet_NaN();
  // The runner tells the controller, before report, that the robot fell (report then says so
  // instead of any success); fall() is FallCause::kNone otherwise.
  void NoteFall(const FallEvent& event) { fall_ = event; }
  const FallEvent& fall() const { return fall_; }
  // The controller's own verdict on its run, asked after deactivate: "" when it did what it was
  // asked as far as it can verify from its measurements, else what went wrong (the runner exits
  // kExitFailed with it). The default: nothing to verify.
  virtual std::string failure() const { return std::string(); }
  // A hold of the self-collision guard leaves the controller's motion not done (playback: the
  // motion is the trajectory): the runner then exits kExitFailed naming the pair. The default:
  // no, the controller's failure() judges whether its goal was reached.
  virtual bool hold_is_failure() const { return false; }
  // The self-collision guard may replace this controller's commands by its brake. False (walk):
  // the guard only monitors (SelfCollisionGuard::set_monitor_only), and links measured closer
  // than their limit fail the run instead.
  virtual bool guard_may_brake() const { return true; }
  // The guard may brake a leg whose foot carries no load (SelfCollisionGuard::
  // set_brake_unloaded_legs; a loaded leg is never braked). False (balance, walk): a leg that
  // leaves the ground is part of the balance (a swing leg braked mid-step is not placed: the
  // walks fell), so every leg with a foot is treated as loaded and its pairs are monitored.
  virtual bool guard_may_brake_legs() const { return true; }

  // Camera images (shm_bridge/images.h). The cameras this controller wants (bit i: camera i of
  // the header), valid from kInactive on: the runner asks the producer for them after
  // configure (and fails with exit 3 when it cannot) and, in each cycle, before update, hands
  // each new frame to on_image. The defaults: no camera. on_image does not allocate, throw or
  // log.
  virtual uint32_t cameras() const { return 0; }
  virtual void on_image(int camera, const shm::ImageSlot& image) noexcept {
    (void)camera;
    (void)image;
  }

 protected:
  Controller() = default;
  virtual ConfigStatus on_configure(const shm::SegmentHeader& header) = 0;
  virtual void on_activate(const shm::SensorBlock& sensors) noexcept = 0;
  virtual void on_update(const shm::SensorBlock& sensors,
                         shm::CommandBlock* commands) noexcept = 0;
  virtual void on_deactivate() noexcept {}
  virtual void on_close() {}

 private:
  void Guard(const shm::SensorBlock& sensors, shm::CommandBlock* commands) noexcept;

  LifecycleState state_ = LifecycleState::kUnconfigured;
  shm::SegmentHeader header_{};
  std::vector<std::string> joint_names_;
  std::array<double, shm::kMaxJoints> last_q_ref_{};  // last good reference, for the hold
  CycleCounters counters_;
  FallEvent fall_;
};

// The joint names of a header, joint-id order (njoint clamped to kMaxJoints).
std::vector<std::string> JointNames(const shm::SegmentHeader& header);

// True when joint j has usable limits (both finite and q_min < q_max).
bool HasLimits(const shm::SegmentHeader& header, int j);

}  // namespace ohrp::controllers
