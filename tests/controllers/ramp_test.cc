// Tests the minimum-jerk ramp (controllers/ramp.h).
#include "controllers/ramp.h"

#include <gtest/gtest.h>

namespace ohrp::controllers {
namespace {

TEST(RampTest, ProfileStartsAndEndsAtRestAndIsMonotone) {
  EXPECT_DOUBLE_EQ(MinimumJerk(0.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerk(1.0), 1.0);
  EXPECT_DOUBLE_EQ(MinimumJerk(0.5), 0.5);
  EXPECT_DOUBLE_EQ(MinimumJerk(-1.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerk(2.0), 1.0);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(0.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(1.0), 0.0);
  EXPECT_DOUBLE_EQ(MinimumJerkRate(0.5), 1.875);  // peak speed 15/8
  double prev = 0.0;
  for (int i = 1; i <= 1000; ++i) {
    const double u = i / 1000.0;
    const double s = MinimumJerk(u);
    EXPECT_GE(s, prev);
    // the rate is the derivative of the profile (central difference, O(h^2))
    const double h = 1e-6;
    if (u < 1.0 - h) {
      EXPECT_NEAR(MinimumJerkRate(u), (MinimumJerk(u + h) - MinimumJerk(u - h)) / (2 * h), 1e-6);
    }
    prev = s;
  }
}

TEST(RampTest, SampleGoesFromCurrentPoseToTarget) {
  const double from[2] = {0.2, -1.0};
  const double to[2] = {1.2, -1.0};
  double q[2], dq[2];
  SampleRamp(from, to, 2, 0.0, 2.0, q, dq);
  EXPECT_DOUBLE_EQ(q[0], 0.2);
  EXPECT_DOUBLE_EQ(dq[0], 0.0);
  SampleRamp(from, to, 2, 1.0, 2.0, q, dq);
  EXPECT_DOUBLE_EQ(q[0], 0.7);
  EXPECT_DOUBLE_EQ(dq[0], 1.0 * 1.875 / 2.0);
  EXPECT_DOUBLE_EQ(q[1], -1.0);
  EXPECT_DOUBLE_EQ(dq[1], 0.0);
  SampleRamp(from, to, 2, 5.0, 2.0, q, dq);  // after the ramp: the target, at rest
  EXPECT_DOUBLE_EQ(q[0], 1.2);
  EXPECT_DOUBLE_EQ(dq[0], 0.0);
}

TEST(RampTest, ZeroDurationJumps) {
  const double from[1] = {0.0};
  const double to[1] = {1.0};
  double q[1], dq[1];
  SampleRamp(from, to, 1, 0.0, 0.0, q, dq);
  EXPECT_DOUBLE_EQ(q[0], 1.0);
  EXPECT_DOUBLE_EQ(dq[0], 0.0);
}

}  // namespace
}  // namespace ohrp::controllers
