// The driver's verification of the boards (issue 28, item 2): every cycle, what the boards
// report is held against what the driver commanded and against what a robot can read.
//
//   plausibility  each joint's position finite and within its range plus a margin (a tenth of
//                 the range; unlimited joints: finite only), its velocity finite and at most
//                 kMaxJointSpeed, its torque finite. A read with an implausible joint is no
//                 valid read (like a NaN): its values never become a reference.
//   servo state   (io_report::kServoState) each joint's servo as commanded, after the boards
//                 had a sustain time to follow a change.
//   acknowledgement (io_report::kBoards) no board leaves the commands unacknowledged
//                 (IoState::unacked_boards: for the plugin's board timeout).
//   tracking      (io_report::kFollowsCommands) a position-mode joint with its servo on: the
//                 error its stiffness fights, (kp e + kd (dq_ref - dq) + tau_ff) / kp with e the
//                 reference minus the reading, stays within tau_max / kp (the error at which its
//                 servo saturates: beyond it the motor cannot pull the joint back harder; the
//                 damping and feed-forward terms explain the lag of a joint following a moving
//                 reference), at least 0.05 rad, except for `tracking_time` at most.
//   refusal, foreign commands (io_report::kBoards) a board refusing the driver's command
//                 (refused_boards) or reporting refused commands of another sender
//                 (foreign_boards).
// Each check counts consecutive cycles per joint (per board for the masks); a disagreement that
// lasts `sustain` cycles (tracking: tracking_time) is a Finding: what, which board and joint,
// the value read. Allocation-free after construction.
#pragma once

#include <cstdint>
#include <vector>

#include "hw_driver/robot_io.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw {

enum class CheckKind : uint8_t {
  kNone,
  kImplausible,     // a reading outside what the joint can read (value: the reading)
  kServoMismatch,   // the servo is not as commanded (value: the servo reported, 0 or 1)
  kUnacknowledged,  // the board does not acknowledge the commands sent (value: board mask)
  kTracking,        // measured position too far from the reference for too long (value: error)
  kRefused,         // the board refused the driver's command (value: board mask)
  kForeign,         // the board refused commands of another sender (value: board mask)
};

struct Finding {
  CheckKind kind = CheckKind::kNone;
  int board = -1;      // -1: the plugin does not say
  int joint = -1;      // -1: a board's finding
  double value = 0;    // see CheckKind
};

class BoardChecks {
 public:
  // `sustain`: cycles a servo or acknowledgement disagreement may last; `tracking_cycles`:
  // cycles a tracking error may last.
  BoardChecks(const shm::ProducerConfig& robot, int sustain, int tracking_cycles);

  // Plausibility of one read: the first implausible joint, or kNone. Counts nothing.
  Finding Plausible(const IoState& in) const noexcept;

  // The boards' obedience this cycle: `servo_on[j]` as commanded and `refs` the references
  // written in the previous cycle; `skip[j]`: joints not held to their command now (re-arming).
  // Returns a finding once a disagreement lasted its sustain time; kNone otherwise.
  Finding Obeyed(const IoState& in, const bool* servo_on, const shm::JointCommand* refs,
                 const bool* skip) noexcept;
  // Forget the counts (after a servo-on or a re-arm: the boards get their sustain time again).
  void Restart() noexcept;

  double tracking_bound(int j) const { return track_bound_[j]; }  // for kp = the default kp

  static int BoardOf(const IoState& in, int joint) {
    return (in.reports & io_report::kBoards) ? in.joint_board[joint] : -1;
  }

 private:
  int njoint_;
  int sustain_, tracking_cycles_;
  std::vector<double> q_lo_, q_hi_, tau_max_, track_bound_;
  std::vector<int> servo_count_, track_count_;
  int unacked_count_ = 0;
};

// The tilt of the IMU's frame against its frame at `reference` (both quaternions w, x, y, z in
// the world): the angle between their z axes [rad]; NaN when either is not a unit quaternion.
double TiltBetween(const double* reference, const double* quat);

}  // namespace ohrp::hw
