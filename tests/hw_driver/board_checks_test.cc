// BoardChecks' tracking check against the servo's law (issue 31): a position-mode joint is held
// to the error its stiffness fights, (kp e + kd (dq_ref - dq) + tau_ff) / kp, within
// tau_max / kp (at least 0.05 rad), for a few cycles at most. Closed forms on one joint with
// G1's waist roll (tau_max 50 N m, kp 889 N m/rad, kd 31 N m s/rad: bound 50 / 889 = 0.0562 rad).
#include <gtest/gtest.h>

#include "hw_driver/board_checks.h"

namespace ohrp::hw {
namespace {

constexpr double kTauMax = 50, kKp = 889, kKd = 31;
constexpr int kCycles = 5;  // tracking cycles allowed

struct OneJoint {
  shm::ProducerConfig robot;
  IoState in;
  shm::JointCommand ref;
  bool on = true, skip = false;
  OneJoint() {
    robot.joint_names = {"waist_roll_joint"};
    robot.q_min = {-0.52};
    robot.q_max = {0.52};
    robot.tau_max = {kTauMax};
    robot.default_kp = {kKp};
    robot.default_kd = {kKd};
    in.reports = io_report::kFollowsCommands;
    ref.mode = shm::JointMode::kPosition;
    ref.kp = kKp;
    ref.kd = kKd;
  }
  // the finding after `n` cycles of the same reading
  CheckKind After(int n) {
    BoardChecks checks(robot, 3, kCycles);
    Finding f;
    for (int i = 0; i < n && f.kind == CheckKind::kNone; ++i) f = checks.Obeyed(in, &on, &ref, &skip);
    return f.kind;
  }
};

// 0.058 rad behind a reference moving at 1.5 rad/s with dq_ref = 0: the damping term asks
// 31 x 1.5 = 46.5 N m against the 51.6 N m of the stiffness, 5.1 N m in all, far from 50 N m
TEST(BoardChecks, AJointLaggingAMovingReferenceByWhatItsDampingExplainsObeys) {
  OneJoint j;
  j.ref.q_ref = 0.058;
  j.in.q[0] = 0.0;
  j.in.dq[0] = 1.5;
  EXPECT_EQ(j.After(10 * kCycles), CheckKind::kNone);
}

// the same error standing still: 51.6 N m asked, beyond 50 N m: the servo saturated, a
// tracking error once it lasted its cycles (and not before)
TEST(BoardChecks, TheSameErrorStandingStillIsATrackingError) {
  OneJoint j;
  j.ref.q_ref = 0.058;
  j.in.q[0] = 0.0;
  j.in.dq[0] = 0.0;
  EXPECT_EQ(j.After(kCycles - 1), CheckKind::kNone);
  EXPECT_EQ(j.After(kCycles), CheckKind::kTracking);
}

// the feed-forward is part of the law: a joint held 0.058 rad below its reference against a
// load the feed-forward does not carry (tau_ff = -10 N m) asks 41.6 N m: no error
TEST(BoardChecks, TheFeedForwardCountsInTheLaw) {
  OneJoint j;
  j.ref.q_ref = 0.058;
  j.ref.tau_ff = -10.0;
  EXPECT_EQ(j.After(10 * kCycles), CheckKind::kNone);
  j.ref.tau_ff = +10.0;  // 61.6 N m asked: saturated
  EXPECT_EQ(j.After(10 * kCycles), CheckKind::kTracking);
}

// moving away from its reference (dq against e) adds to what the servo asks
TEST(BoardChecks, AJointRunningAwayFromItsReferenceIsATrackingErrorSooner) {
  OneJoint j;
  j.ref.q_ref = 0.03;  // 26.7 N m of stiffness alone: within the limit
  j.in.dq[0] = -1.0;   // + 31 N m of damping: 57.7 N m asked
  EXPECT_EQ(j.After(10 * kCycles), CheckKind::kTracking);
}

}  // namespace
}  // namespace ohrp::hw
