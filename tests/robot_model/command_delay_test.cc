// The actuators' command delay (robot_model/command_delay.h): each joint's command comes out the
// given number of shifts later, the others at once; an override reaches every pending block.
#include "robot_model/command_delay.h"

#include <gtest/gtest.h>

namespace ohrp::model {
namespace {

TEST(CommandDelay, EachJointsBlockComesOutItsNumberOfShiftsLater) {
  shm::CommandBlock initial{}, b{};
  initial.njoint = b.njoint = 3;
  CommandDelay d;
  d.SetUp({3, 0, 1}, initial);  // joint 0: 3 cycles, joint 1: none, joint 2: 1
  EXPECT_EQ(d.cycles(), 3);
  for (int k = 1; k <= 10; ++k) {
    for (int j = 0; j < 3; ++j) b.joint[j].q_ref = k;
    const shm::CommandBlock& out = d.Shift(b);
    EXPECT_EQ(out.joint[0].q_ref, k > 3 ? k - 3 : 0.0) << k;  // the initial block for the first 3
    EXPECT_EQ(out.joint[1].q_ref, k) << k;
    EXPECT_EQ(out.joint[2].q_ref, k > 1 ? k - 1 : 0.0) << k;
  }
  shm::JointCommand off{};
  off.q_ref = -1;
  d.Override(0, off);  // every pending block
  for (int k = 0; k < 3; ++k) EXPECT_EQ(d.Shift(b).joint[0].q_ref, -1.0);
  EXPECT_EQ(d.Shift(b).joint[0].q_ref, 10.0);
  CommandDelay none;
  none.SetUp({0, 0}, initial);
  EXPECT_EQ(none.cycles(), 0);
  EXPECT_EQ(&none.Shift(b), &b);  // no delay: the block itself
}

}  // namespace
}  // namespace ohrp::model
