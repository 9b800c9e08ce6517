// The driver's command checks: what a controller's command block must satisfy before it
// reaches the motor boards, and the references the boards get when the driver, not the
// controller, decides (servo-on hold, safe mode, servo-off damping).
//
// Checks (sim_host's, model::CommandAcceptable in robot_model/servo.h, applied on the robot):
// joint by joint, a command whose values are not finite, whose mode is unknown, whose position
// reference lies outside the joint's range by more than kRangeTolerance, whose velocity
// reference exceeds kMaxJointSpeed, whose gains are negative or above kMaxGain, or whose
// feed-forward torque exceeds the joint's torque limit is rejected: the joint keeps its
// previous reference (it holds) and the rejection is counted per joint. A block for another
// number of joints is rejected whole. Accepted position references are clamped into the
// joint's range. Nothing here allocates after construction.
#pragma once

#include <cstdint>
#include <vector>

#include "robot_model/servo.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw {

// the servo's bounds (robot_model/servo.h), under the names the driver's tests use
inline constexpr double kMaxGain = model::kMaxGain;              // kp, kd above: refused
inline constexpr double kRangeTolerance = model::kRangeTolerance;  // [rad or m]
inline constexpr double kMaxJointSpeed = model::kMaxJointSpeed;    // |dq_ref| above [rad/s or m/s]

class CommandGuard {
 public:
  // `robot`: joint limits, torque limits and default gains (njoint entries each).
  explicit CommandGuard(const shm::ProducerConfig& robot);

  // Position hold of `q` (njoint) with the default gains: the servo-on references.
  void HoldMeasured(const double* q) noexcept;

  // Checks `commands` joint by joint; valid joints take the (clamped) command as their new
  // reference. Returns the number of joints rejected.
  int Accept(const shm::CommandBlock& commands) noexcept;

  // Turns the references into a damped hold: position mode at the last position reference
  // (the measured position `q` for joints not in position mode), no feed-forward, gains = the
  // default gains times the scales. Used by the safe mode and the servo-off sequence.
  void Damp(const double* q, double kp_scale, double kd_scale) noexcept;

  // Sets joint `i`'s reference as the driver decides (the re-arm after a board reset): the
  // command is clamped into the joint's range when in position mode; refused (false, the
  // reference kept) when not Valid.
  bool Set(int i, const shm::JointCommand& c) noexcept;

  int njoint() const { return static_cast<int>(ref_.size()); }
  double default_kp(int i) const { return kp_[i]; }
  double default_kd(int i) const { return kd_[i]; }
  const shm::JointCommand* references() const { return ref_.data(); }
  const uint32_t* rejected_per_joint() const { return rejected_.data(); }
  uint64_t rejected_total() const { return rejected_total_; }
  uint64_t clamped_total() const { return clamped_total_; }  // position references clamped

  // True when `c` may be sent to joint `i` (the checks above).
  bool Valid(int i, const shm::JointCommand& c) const noexcept;

 private:
  std::vector<double> q_min_, q_max_, tau_max_, kp_, kd_;
  std::vector<shm::JointCommand> ref_;
  std::vector<uint32_t> rejected_;
  uint64_t rejected_total_ = 0;
  uint64_t clamped_total_ = 0;
};

}  // namespace ohrp::hw
