// The joint servos, as the robot's motor drivers run them: each physics step, a PD law on the
// references of the last accepted command, clamped to the joint's torque limit.
//
// Commands are checked joint by joint when they arrive (Accept): a joint whose command is not
// finite, names an unknown mode, asks for a position outside the joint's range, negative or
// absurd gains, or a feed-forward torque above the limit is rejected and keeps its previous
// reference (it holds); the rejection is counted per joint. Nothing here allocates.
#pragma once

#include <cstdint>
#include <vector>

#include "shm_bridge/layout.h"
#include "robot_model/model.h"

namespace ohrp::model {

inline constexpr double kMaxGain = 1e7;            // kp [N m/rad] or kd [N m s/rad] above this is refused
inline constexpr double kRangeTolerance = 1e-3;    // position reference may exceed the range by this [rad]

class Servo {
 public:
  explicit Servo(const RobotMap& robot);

  // Holds the current positions (position mode, default gains): the servo state at power-on.
  void HoldCurrent(const mjData* d);

  // Takes a command block joint by joint. Returns the number of joints rejected this time.
  int Accept(const shm::CommandBlock& commands);

  // Writes the servo torques into d->ctrl from the state in `d`. Call before each mj_step.
  void Apply(const mjModel* m, mjData* d) const;

  const shm::JointCommand& reference(int i) const { return ref_[i]; }
  uint64_t rejected_total() const { return rejected_total_; }
  const uint32_t* rejected_per_joint() const { return rejected_.data(); }

 private:
  bool Valid(int i, const shm::JointCommand& c) const;
  const RobotMap& robot_;
  std::vector<shm::JointCommand> ref_;
  std::vector<uint32_t> rejected_;
  uint64_t rejected_total_ = 0;
};

}  // namespace ohrp::model
