// The joint servos, as the robot's motor drivers run them: each physics step, a PD law on the
// references of the last accepted command, clamped to the joint's torque limit.
//
// Commands are checked joint by joint when they arrive (Accept, with CommandAcceptable): a
// joint whose command is not finite, names an unknown mode, asks for a position outside the
// joint's range, a velocity beyond kMaxJointSpeed, negative or absurd gains, or a feed-forward
// torque above the limit is rejected and keeps its previous reference (it holds); the rejection
// is counted per joint. Nothing here allocates.
//
// The PD law gives a joint torque; Apply turns it into the control of the joint's actuator
// (JointMap::law, actuator.h: ctrl = tau/gear for a motor, the affine law inverted for
// <position>, <velocity> and <general>). A step in which ctrlrange or forcerange kept the joint
// short of its torque is counted per joint (clamped_per_joint).
//
// Velocity references: neither the MJCF nor the segment carries a per-joint velocity limit, so
// the bound is one speed for every joint, kMaxJointSpeed. Humanoid joints run below about
// 20 rad/s (HRP-1S's below 10 rad/s), so a reference above 100 rad/s (or 100 m/s on a slider)
// is a controller's bug, not a motion: with any damping gain it would only saturate the joint's
// torque. It applies in position and velocity modes (the modes that use dq_ref).
#pragma once

#include <cstdint>
#include <vector>

#include "shm_bridge/layout.h"
#include "robot_model/model.h"

namespace ohrp::model {

inline constexpr double kMaxGain = 1e7;            // kp [N m/rad] or kd [N m s/rad] above this is refused
inline constexpr double kRangeTolerance = 1e-3;    // position reference may exceed the range by this [rad]
inline constexpr double kMaxJointSpeed = 100.0;    // |dq_ref| above this is refused [rad/s or m/s]

// True when command `c` may reach a joint of range [q_min, q_max] (either may be infinite) and
// torque limit `tau_max` (>= 0): every value finite, a known mode, and for the modes that use
// them q_ref within the range (+- kRangeTolerance), |dq_ref| <= kMaxJointSpeed, gains in
// [0, kMaxGain], |tau_ff| <= tau_max. The one check of sim_host's servo and hw_driver's guard.
bool CommandAcceptable(const shm::JointCommand& c, double q_min, double q_max,
                       double tau_max) noexcept;

class Servo {
 public:
  explicit Servo(const RobotMap& robot);

  // Holds the current positions (position mode, default gains): the servo state at power-on.
  void HoldCurrent(const mjData* d);

  // Takes a command block joint by joint. Returns the number of joints rejected this time.
  int Accept(const shm::CommandBlock& commands);

  // Writes the servo torques, as the actuators' controls, into d->ctrl from the state in `d`.
  // Call before each mj_step. Counts the joints whose actuator could not give the torque.
  void Apply(const mjModel* m, mjData* d);

  const shm::JointCommand& reference(int i) const { return ref_[i]; }
  uint64_t rejected_total() const { return rejected_total_; }
  const uint32_t* rejected_per_joint() const { return rejected_.data(); }
  // physics steps in which joint i's actuator clamped (ctrlrange or forcerange)
  uint64_t clamped(int i) const { return clamped_[i]; }
  uint64_t clamped_total() const { return clamped_total_; }

 private:
  bool Valid(int i, const shm::JointCommand& c) const;
  const RobotMap& robot_;
  std::vector<shm::JointCommand> ref_;
  std::vector<uint32_t> rejected_;
  uint64_t rejected_total_ = 0;
  std::vector<uint64_t> clamped_;
  uint64_t clamped_total_ = 0;
};

}  // namespace ohrp::model
