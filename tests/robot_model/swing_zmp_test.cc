// Tests the swinging legs' share of the ZMP (walking::SwingZmpGain, PatternGenerator's
// SetSwingZmpGain) against closed forms: the gain of point masses on a leg turning about the hip,
// and the share the generator adds during a swing against the minimum-jerk travel's peak
// acceleration 10 / sqrt(3) D / T^2; that peak against the gait's own swing, and the most the
// hip lets a foot accelerate (SwingPeakAcceleration, SwingAccelerationLimit).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "walking/pattern_generator.h"

namespace ohrp::walking {
namespace {

constexpr double kG = 9.81;

// kappa = sum m_i s_i (z_r - z_i) / (M g), s_i = (hip - z_i) / hip clamped to [0, 1], z_r the rest's CoM
TEST(SwingZmpGain, PointMassesOnALegTurningAboutTheHip) {
  const double M = 100, c = 0.8, hip = 0.6;
  const std::vector<LegBody> leg = {{5, 0.3}, {3, 0.0}, {2, 0.7}, {1, -0.05}};
  const double m_leg = 11, moment = 5 * 0.3 + 0 + 2 * 0.7 + 1 * -0.05;
  const double z_r = (M * c - moment) / (M - m_leg);
  // the body above the hip moves with none of the foot's acceleration, the one below the sole
  // with all of it
  const double expected = (5 * 0.5 * (z_r - 0.3) + 3 * 1.0 * z_r + 1 * 1.0 * (z_r + 0.05)) / (M * kG);
  EXPECT_NEAR(SwingZmpGain(leg, hip, c, M, kG), expected, 1e-12);
  // nothing to say without a hip, or with a leg as heavy as the robot
  EXPECT_EQ(SwingZmpGain(leg, 0, c, M, kG), 0);
  EXPECT_EQ(SwingZmpGain(leg, hip, c, 11, kG), 0);
  EXPECT_EQ(SwingZmpGain({}, hip, c, M, kG), 0);
}

// during a swing the generator's zmp_swing is kappa times the swing foot's acceleration: its
// largest forward value is kappa 10 / sqrt(3) D / T^2 (the minimum-jerk travel of D = 2 strides
// over T, the single support less its vertical shares); the CoM plan carries the opposite, so
// that the cart's ZMP plus the legs' share is on the gait's reference
TEST(SwingZmpGain, GeneratorAddsTheSwingFootsAccelerationTimesTheGain) {
  const double kappa = 0.005, stride = 0.2, dt = 0.005;
  GaitOptions go;
  PreviewOptions p;
  p.dt = dt;
  p.zc = 0.8;
  PatternGenerator g;
  std::string error;
  ASSERT_TRUE(g.Configure(go, p, &error)) << error;
  FeetPose f;
  f.p[kLeft] = Eigen::Vector3d(0, 0.08, 0);
  f.p[kRight] = Eigen::Vector3d(0, -0.08, 0);
  ASSERT_TRUE(g.Start(0, f, Eigen::Vector3d(0, 0, 0.8), &error)) << error;
  g.SetSwingZmpGain(kappa);
  std::vector<Footstep> steps;
  for (int k = 0; k < 6; ++k) {
    Footstep s;
    s.foot = k % 2 == 0 ? kRight : kLeft;
    s.p = Eigen::Vector3d((k + 1) * stride, s.foot == kLeft ? 0.08 : -0.08, 0);
    steps.push_back(s);
  }
  g.Replace(steps);
  const Gait& gait = g.gait();
  // step 2: a full stride from behind to ahead (2 strides of travel)
  const double T = (gait.step_land(2) - gait.step_lift(2)) * (1 - 2 * go.vertical_fraction);
  const double peak = kappa * 10 / std::sqrt(3.0) * 2 * stride / (T * T);
  double largest = 0, smallest = 0, worst_sum = 0;
  while (g.sample().t < gait.step_land(2) + 1.0) {
    const WalkSample& w = g.Advance();
    if (w.t > gait.step_lift(2) && w.t < gait.step_land(2)) {
      largest = std::max(largest, w.zmp_swing.x());
      smallest = std::min(smallest, w.zmp_swing.x());
      EXPECT_NEAR(w.zmp_swing.y(), 0, 1e-9);
    }
    if (w.t > gait.step_lift(1))
      worst_sum = std::max(worst_sum, std::abs(w.zmp.x() + w.zmp_swing.x() - w.gait.zmp.x()));
  }
  EXPECT_NEAR(largest, peak, 0.02 * peak);
  EXPECT_NEAR(smallest, -peak, 0.02 * peak);
  // the preview tracks the reference less the share to within what it tracks the cart's own
  // reference (a few mm at the double supports' corners)
  EXPECT_LT(worst_sum, 0.02);
}

// the swing foot's peak acceleration on the flat, against the gait's own swing sampled every
// 0.1 ms (second differences): 10/sqrt(3) D / T^2 over T = step (1 - ds) (1 - 2 vf)
TEST(SwingPeakAcceleration, MatchesTheGaitsSwing) {
  for (double vf : {0.0, 0.05}) {
    GaitOptions o;
    o.step_time = 0.6;
    o.double_support_ratio = 0.05;
    o.vertical_fraction = vf;
    FeetPose f;
    f.p[kLeft] = Eigen::Vector3d(0, 0.08, 0);
    f.p[kRight] = Eigen::Vector3d(0, -0.08, 0);
    Gait gait;
    gait.Start(0, f, o);
    Footstep s;
    s.foot = kRight;
    s.p = Eigen::Vector3d(0.36, -0.08, 0);
    gait.Replace(0, {s});
    const double h = 1e-4;
    double peak = 0;
    GaitState a, b, c;
    for (double t = gait.step_lift(0) + h; t < gait.step_land(0) - h; t += h) {
      gait.At(t - h, &a);
      gait.At(t, &b);
      gait.At(t + h, &c);
      peak = std::max(peak, std::abs(c.feet.p[kRight].x() - 2 * b.feet.p[kRight].x() + a.feet.p[kRight].x()) / (h * h));
    }
    const double T = 0.6 * 0.95 * (1 - 2 * vf);
    EXPECT_NEAR(SwingPeakAcceleration(o, 0.36), 10 / std::sqrt(3.0) * 0.36 / (T * T), 1e-9);
    EXPECT_NEAR(peak, SwingPeakAcceleration(o, 0.36), 0.01 * peak) << "vf " << vf;
  }
}

// (tau_max - tau_gravity) hip / inertia; no more than none when gravity takes all the torque
TEST(SwingAccelerationLimit, TorqueLessGravityOverInertiaAtTheFoot) {
  EXPECT_NEAR(SwingAccelerationLimit(400, 25, 15, 0.6), 375 * 0.6 / 15, 1e-12);
  EXPECT_EQ(SwingAccelerationLimit(400, 500, 15, 0.6), 0);
  EXPECT_TRUE(std::isinf(SwingAccelerationLimit(400, 25, 0, 0.6)));
}

// a swing retimed (Gait::AdjustStep) at `phase` to land `rest` later, SwingReachDistance away
// from where the foot is: its horizontal acceleration over the rest (second differences every
// 0.1 ms) peaks at the limit given when the remaining travel still holds the profile's peak (at
// lift-off), and never above it later in the swing
TEST(SwingReachDistance, ARetimedSwingPeaksAtTheLimit) {
  const double accel = 40, vf = 0.05;
  GaitOptions o;
  o.step_time = 0.8;
  o.double_support_ratio = 0.1;
  o.vertical_fraction = vf;
  for (double phase : {0.0, 0.3}) {
    FeetPose f;
    f.p[kLeft] = Eigen::Vector3d(0, 0.09, 0);
    f.p[kRight] = Eigen::Vector3d(0, -0.09, 0);
    Gait gait;
    gait.Start(0, f, o);
    Footstep s;
    s.foot = kRight;
    s.p = Eigen::Vector3d(0.2, -0.09, 0);
    gait.Replace(0, {s});
    const double t_lift = gait.step_lift(0), single = gait.step_land(0) - t_lift;
    const double now = t_lift + phase * single + 1e-9, rest = 0.3;
    GaitState g;
    gait.At(now, &g);
    const double D = SwingReachDistance(accel, g.swing_phase, vf, rest);
    const Eigen::Vector2d foot = g.feet.p[kRight].head<2>();
    const Eigen::Vector2d target = foot + D * Eigen::Vector2d(1, 0);
    ASSERT_TRUE(gait.AdjustStep(0, target, now + rest, false, now));
    const double h = 1e-4;
    double peak = 0;
    GaitState a, b, c;
    for (double t = now + h; t < now + rest - h; t += h) {
      gait.At(t - h, &a);
      gait.At(t, &b);
      gait.At(t + h, &c);
      peak = std::max(peak, (c.feet.p[kRight].head<2>() - 2 * b.feet.p[kRight].head<2>() +
                             a.feet.p[kRight].head<2>()).norm() / (h * h));
    }
    EXPECT_LE(peak, accel * 1.01) << "phase " << phase;
    if (phase == 0) {
      EXPECT_NEAR(peak, accel, 0.01 * accel);
    }
  }
  EXPECT_TRUE(std::isinf(SwingReachDistance(std::numeric_limits<double>::infinity(), 0.5, vf, 0.2)));
}

}  // namespace
}  // namespace ohrp::walking
