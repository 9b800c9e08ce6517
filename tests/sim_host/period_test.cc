// Tests the control period's choice (sim_host/period.h): by default the multiple of the scene's
// step nearest 5 ms; an explicit period that is not a multiple names the ones that are.
#include "sim_host/period.h"

#include <gtest/gtest.h>

namespace ohrp::sim {
namespace {

struct Chosen {
  double period = 0;
  int steps = 0;
};

Chosen Default(double dt) {
  Chosen c;
  std::string error;
  EXPECT_TRUE(ChooseControlPeriod(dt, 0, &c.period, &c.steps, &error)) << error;
  return c;
}

TEST(ControlPeriod, DefaultFollowsTheScenesStep) {
  EXPECT_EQ(Default(0.001).steps, 5);     // HRP-1S: 5 ms
  EXPECT_EQ(Default(0.0005).steps, 10);   // Cassie: 5 ms
  EXPECT_EQ(Default(0.005).steps, 1);     // MuJoCo's humanoid: 5 ms
  EXPECT_EQ(Default(0.02).steps, 1);      // a coarse step: one step per cycle
  EXPECT_EQ(Default(0.003).steps, 2);     // 6 ms is nearer 5 ms than 3 ms
  const Chosen h1 = Default(0.002);       // Unitree H1: 4 ms and 6 ms tie, the shorter wins
  EXPECT_EQ(h1.steps, 2);
  EXPECT_DOUBLE_EQ(h1.period, 0.004);
}

TEST(ControlPeriod, ExplicitMultipleIsKept) {
  double period = 0;
  int steps = 0;
  std::string error;
  ASSERT_TRUE(ChooseControlPeriod(0.002, 0.006, &period, &steps, &error)) << error;
  EXPECT_DOUBLE_EQ(period, 0.006);
  EXPECT_EQ(steps, 3);
}

TEST(ControlPeriod, ExplicitPeriodThatDoesNotDivideNamesTheOnesThatWould) {
  double period = 0;
  int steps = 0;
  std::string error;
  EXPECT_FALSE(ChooseControlPeriod(0.002, 0.005, &period, &steps, &error));
  EXPECT_NE(error.find("use --control-period 0.004 or 0.006"), std::string::npos) << error;
  EXPECT_NE(error.find("leave it out: 0.004 s"), std::string::npos) << error;
  EXPECT_FALSE(ChooseControlPeriod(0.002, 0.001, &period, &steps, &error));  // below one step
  EXPECT_NE(error.find("0.002 or 0.004"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::sim
