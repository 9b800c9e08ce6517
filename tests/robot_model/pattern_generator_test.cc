// Tests the walking pattern generator against closed forms: the cart-table model against the
// LIPM's solution, the preview servo's ZMP tracking of a stepwise reference, the CoM at rest over
// the last support, the swing feet landing where planned, online replacement without a jump,
// and the legs' IK reproducing the planned feet and CoM on HRP-1S.
#include "walking/pattern_generator.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_models.h"
#include "walking/walk_ik.h"

namespace ohrp::walking {
namespace {

constexpr double kG = 9.81;

FeetPose Stance(double width = 0.16) {
  FeetPose f;
  f.p[kLeft] = Eigen::Vector3d(0, width / 2, 0);
  f.p[kRight] = Eigen::Vector3d(0, -width / 2, 0);
  f.yaw[0] = f.yaw[1] = 0;
  return f;
}

// n steps forward of `stride`, right foot first, and a closing step
std::vector<Footstep> Straight(int n, double stride, double width = 0.16) {
  std::vector<Footstep> steps;
  for (int k = 0; k < n; ++k) {
    Footstep s;
    s.foot = k % 2 == 0 ? kRight : kLeft;
    s.p = Eigen::Vector3d((k + 1) * stride, s.foot == kLeft ? width / 2 : -width / 2, 0);
    steps.push_back(s);
  }
  Footstep close;
  close.foot = n % 2 == 0 ? kRight : kLeft;
  close.p = Eigen::Vector3d(n * stride, close.foot == kLeft ? width / 2 : -width / 2, 0);
  steps.push_back(close);
  return steps;
}

PatternGenerator Make(double dt = 0.005, double zc = 0.8) {
  PatternGenerator g;
  std::string error;
  PreviewOptions p;
  p.dt = dt;
  p.zc = zc;
  EXPECT_TRUE(g.Configure(GaitOptions{}, p, &error)) << error;
  EXPECT_TRUE(g.Start(0, Stance(), Eigen::Vector3d(0, 0, zc), &error)) << error;
  return g;
}

// the cart-table model driven by the LIPM's own jerk keeps the ZMP still and follows
// x(t) = x0 cosh(t/Tc) + Tc v0 sinh(t/Tc) (about p = 0); piecewise-constant jerk over 1 ms makes
// an error of order dt: 1e-4 relative over 1 s is the stated bound
TEST(PreviewControl, CartTableFollowsTheLipmClosedForm) {
  PreviewGains g;
  std::string error;
  PreviewOptions o;
  o.dt = 0.001;
  o.zc = 0.8;
  ASSERT_TRUE(g.Compute(o, &error)) << error;
  const double Tc = std::sqrt(o.zc / kG), x0 = 0.02, v0 = 0.1;
  Eigen::Vector3d x(x0, v0, x0 / (Tc * Tc));
  double max_rel = 0, max_zmp = 0;
  for (int k = 0; k < 1000; ++k) {
    const double t = k * o.dt, tm = t + o.dt / 2;
    // the closed form's jerk at the middle of the step
    const double jerk = (x0 * std::sinh(tm / Tc) / Tc + v0 * std::cosh(tm / Tc)) / (Tc * Tc);
    x = g.A() * x + g.B() * jerk;
    const double t1 = t + o.dt;
    const double exact = x0 * std::cosh(t1 / Tc) + Tc * v0 * std::sinh(t1 / Tc);
    max_rel = std::max(max_rel, std::abs(x[0] - exact) / std::abs(exact));
    max_zmp = std::max(max_zmp, std::abs(g.C() * x));
  }
  EXPECT_LT(max_rel, 1e-4);
  EXPECT_LT(max_zmp, 1e-4);  // the ZMP stayed at 0 [m]
}

TEST(PreviewControl, RefusesBadOptions) {
  PreviewGains g;
  std::string error;
  PreviewOptions o;
  o.zc = -1;
  EXPECT_FALSE(g.Compute(o, &error));
  EXPECT_NE(error.find("zc"), std::string::npos);
  o = PreviewOptions{};
  o.r = std::nan("");
  EXPECT_FALSE(g.Compute(o, &error));
}

// Kajita 2003's gains: Gd decays like exp(-t / Tc) and is below 1 % of its peak at the end of
// the preview time (the preview is long enough)
TEST(PreviewControl, PreviewGainsDecayOverTheHorizon) {
  PreviewGains g;
  std::string error;
  ASSERT_TRUE(g.Compute(PreviewOptions{}, &error)) << error;
  EXPECT_EQ(g.horizon(), 320);  // 1.6 s at 5 ms
  EXPECT_GT(g.gi(), 0);
  double peak = 0;
  for (double v : g.gd()) peak = std::max(peak, std::abs(v));
  EXPECT_LT(std::abs(g.gd().back()), 0.01 * peak);
}

// at each single support's middle the ZMP of the planned CoM is within 1 cm of the stance foot;
// the walk ends with the CoM at rest within 1 cm of the middle of the last stance
TEST(PatternGenerator, TracksAStepwiseZmpAndEndsAtRest) {
  PatternGenerator g = Make();
  const std::vector<Footstep> steps = Straight(8, 0.2);
  g.Replace(steps);
  const Gait& gait = g.gait();
  int checked = 0;
  while (g.sample().t < gait.end_time() + 3.0) {
    const WalkSample& s = g.Advance();
    for (int k = 0; k < gait.step_count(); ++k) {
      const double mid = 0.5 * (gait.step_lift(k) + gait.step_land(k));
      if (std::abs(s.t - mid) < 1e-9 + 0.0025) {
        EXPECT_LT((s.zmp - s.gait.zmp.head<2>()).norm(), 0.01) << "step " << k << " t " << s.t;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, gait.step_count());
  const Eigen::Vector2d end(8 * 0.2, 0);
  EXPECT_LT((g.sample().com.head<2>() - end).norm(), 0.01);
  EXPECT_LT(g.sample().dcom.head<2>().norm(), 0.01);
}

// the swing foot lands exactly on the planned pose (1 mm stated) and leaves and lands vertically
TEST(PatternGenerator, SwingFeetLandWherePlanned) {
  PatternGenerator g = Make();
  std::vector<Footstep> steps = Straight(4, 0.25);
  steps[1].yaw = 0.3;
  steps[2].p.z() = 0.1;  // onto a stair
  g.Replace(steps);
  const Gait& gait = g.gait();
  for (int k = 0; k < gait.step_count(); ++k) {
    GaitState s;
    gait.At(gait.step_land(k) - 1e-9, &s);
    ASSERT_EQ(s.swing, steps[k].foot);
    EXPECT_LT((s.feet.p[s.swing] - steps[k].p).norm(), 1e-3);
    EXPECT_NEAR(s.feet.yaw[s.swing], steps[k].yaw, 1e-3);
    // vertical take-off and landing: before `vertical_fraction` of the swing (0.3 onto a step
    // of 1 cm or more) the foot has not moved horizontally from its lift-off spot, and after
    // the same before landing (0.3 onto or off a step) it is over its landing spot
    const double rise = steps[k].p.z() - gait.FeetAfter(k - 1).p[steps[k].foot].z();
    const double vf_land = std::abs(rise) > 0.01 ? 0.3 : gait.options().vertical_fraction;
    const double vf_lift = rise > 0.01 ? 0.3 : gait.options().vertical_fraction;
    const double swing = gait.step_land(k) - gait.step_lift(k);
    gait.At(gait.step_lift(k) + 0.5 * vf_lift * swing, &s);
    EXPECT_LT((s.feet.p[s.swing] - gait.FeetAfter(k - 1).p[s.swing]).head<2>().norm(), 1e-9);
    EXPECT_GT(s.feet.p[s.swing].z(), gait.FeetAfter(k - 1).p[s.swing].z());  // it rose
    gait.At(gait.step_land(k) - 0.5 * vf_land * swing, &s);
    EXPECT_LT((s.feet.p[s.swing] - steps[k].p).head<2>().norm(), 1e-9);
    // and the apex is above the higher end by the step height
    gait.At(0.5 * (gait.step_lift(k) + gait.step_land(k)), &s);
    EXPECT_GT(s.feet.p[s.swing].z(), steps[k].p.z() + 0.99 * gait.options().step_height);
  }
}

// replacing the steps not yet started changes the reference ahead, never the CoM now: the
// largest CoM change in one cycle stays that of a walk without replacement
TEST(PatternGenerator, ReplacingStepsKeepsTheCoMContinuous) {
  PatternGenerator g = Make();
  g.Replace(Straight(10, 0.2));
  double max_step = 0;
  Eigen::Vector3d last = g.sample().com;
  Eigen::Vector3d last_v = g.sample().dcom;
  double max_dv = 0;
  int replaced = 0;
  while (g.sample().t < g.gait().end_time() + 1.0) {
    const WalkSample& s = g.Advance();
    max_step = std::max(max_step, (s.com - last).norm());
    max_dv = std::max(max_dv, (s.dcom - last_v).norm());
    last = s.com;
    last_v = s.dcom;
    if (replaced == 0 && s.t > 2.5) {
      // turn left instead of going on: steps from the feet after the step under way
      const int k = s.gait.step;
      ASSERT_GE(k, 0);
      FeetPose feet = s.gait.feet;
      feet.p[g.gait().step(k).foot] = g.gait().step(k).p;
      std::vector<Footstep> turn;
      int foot = 1 - g.gait().step(k).foot;
      for (int i = 0; i < 3; ++i, foot = 1 - foot) {
        Footstep st;
        st.foot = foot;
        st.yaw = 0.2 * (i + 1);
        st.p = feet.p[1 - foot] + Eigen::Vector3d(0.1 - (foot == kLeft ? 0.16 : -0.16) * std::sin(st.yaw),
                                                  (foot == kLeft ? 0.16 : -0.16) * std::cos(st.yaw), 0);
        turn.push_back(st);
        feet.p[foot] = st.p;
      }
      EXPECT_EQ(g.Replace(turn), k + 1);
      replaced = 1;
    }
  }
  EXPECT_EQ(replaced, 1);
  // 0.2 m strides at 0.8 s: the CoM moves about 0.25 m/s; 5 ms at 0.6 m/s is 3 mm
  EXPECT_LT(max_step, 0.003);
  // the velocity changes smoothly too (no step in the CoM's speed): 0.1 m/s per cycle is 20 m/s^2
  EXPECT_LT(max_dv, 0.1 * 0.2);
}

// the legs' IK on HRP-1S reproduces the planned feet to 0.1 mm and the CoM to 0.1 mm along a
// walk with a turn and a step up
TEST(WalkIk, LegsReproduceThePlannedFeetAndCoM) {
  std::string error;
  auto kin = model::testing::Hrp1s(&error);
  ASSERT_TRUE(kin) << error;
  auto ik = WalkIk::Create(kin.get(), &error);
  ASSERT_TRUE(ik) << error;
  // the half-sitting stance: soles and CoM from the model
  std::vector<double> q(kin->njoint(), 0.0);
  for (const std::string leg : {"RLEG", "LLEG"}) {
    q[kin->JointId(leg + "_HIP_P")] = -0.349066;
    q[kin->JointId(leg + "_KNEE")] = 0.698132;
    q[kin->JointId(leg + "_ANKLE_P")] = -0.349066;
  }
  Eigen::Vector3d p_WB(0, 0, 0.68388);
  kin->SetBasePose(p_WB, Eigen::Quaterniond::Identity());
  kin->SetJointPositions(q.data());
  kin->Update();
  FeetPose feet;
  Eigen::Matrix3d R0[2];
  for (int i = 0; i < 2; ++i) {
    feet.p[i] = kin->p_WSole(ik->sole(i));
    feet.yaw[i] = 0;
    R0[i] = kin->R_WSole(ik->sole(i));
  }
  // walking 4 cm lower than half-sitting: the trailing leg's reach when the CoM rises on a step
  const Eigen::Vector3d com0 = kin->p_WCoM() - Eigen::Vector3d(0, 0, 0.04);
  PatternGenerator g;
  PreviewOptions po;
  po.zc = com0.z() - feet.p[0].z();
  ASSERT_TRUE(g.Configure(GaitOptions{}, po, &error)) << error;
  ASSERT_TRUE(g.Start(0, feet, com0, &error)) << error;
  const double w = feet.p[0].y() - feet.p[1].y();
  std::vector<Footstep> steps;
  // forward, onto a 5 cm step turning 0.2 rad, the other foot up beside it
  Footstep a{kRight, Eigen::Vector3d(0.15, -w / 2, 0), 0, -1, -1};
  Footstep b{kLeft, Eigen::Vector3d(0.3, w / 2, 0.05), 0.2, -1, -1};
  Footstep c{kRight, Eigen::Vector3d(0.3 + w * std::sin(0.2), w / 2 - w * std::cos(0.2), 0.05), 0.2, -1, -1};
  steps = {a, b, c};
  g.Replace(steps);
  double max_foot = 0, max_com = 0;
  int fails = 0;
  while (g.sample().t < g.gait().end_time() + 0.5) {
    const WalkSample& s = g.Advance();
    Eigen::Vector3d p[2];
    Eigen::Matrix3d R[2];
    for (int i = 0; i < 2; ++i) {
      p[i] = s.gait.feet.p[i];
      R[i] = Eigen::AngleAxisd(s.gait.feet.yaw[i], Eigen::Vector3d::UnitZ()) * R0[i];
    }
    const double yaw = 0.5 * (s.gait.feet.yaw[0] + s.gait.feet.yaw[1]);
    const Eigen::Quaterniond quat(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    const WalkIkResult r = ik->Solve(s.com, quat, p, R, q.data(), &p_WB);
    if (!r.ok) ++fails;
    kin->SetBasePose(p_WB, quat);
    kin->SetJointPositions(q.data());
    kin->Update();
    for (int i = 0; i < 2; ++i) max_foot = std::max(max_foot, (kin->p_WSole(ik->sole(i)) - p[i]).norm());
    max_com = std::max(max_com, (kin->p_WCoM() - s.com).norm());
  }
  EXPECT_EQ(fails, 0);
  EXPECT_LT(max_foot, 1e-4);
  EXPECT_LT(max_com, 1e-4);
}


}  // namespace
}  // namespace ohrp::walking

namespace ohrp::walking {
namespace {

// a step down lowers the ground under the CoM by the closed form of the landing leg's reach:
// hip `h` above the stance sole, landing `depth` below it and `reach_xy` ahead, the hip midway:
// (h - drop + depth)^2 + (reach_xy / 2)^2 = leg_reach^2; nothing for a step up or on the flat
TEST(Gait, StepDownLowersTheCoMAsFarAsTheLandingLegNeeds) {
  GaitOptions o;
  o.leg_reach = 0.70;
  o.hip_height = 0.60;
  const double depth = 0.15, reach_xy = 0.32;
  const double drop = StepDownDrop(o, depth, reach_xy);
  EXPECT_NEAR(drop, 0.60 + 0.15 - std::sqrt(0.70 * 0.70 - 0.16 * 0.16), 1e-12);
  EXPECT_NEAR(std::hypot(o.hip_height - drop + depth, reach_xy / 2), o.leg_reach, 1e-12);
  EXPECT_EQ(StepDownDrop(o, -0.15, reach_xy), 0.0);        // up
  EXPECT_EQ(StepDownDrop(o, 0.0, reach_xy), 0.0);          // flat
  EXPECT_EQ(StepDownDrop(o, 0.02, 0.1), 0.0);              // a small step down: within reach
  EXPECT_NEAR(StepDownDrop(o, 0.5, 2.0), 0.5, 1e-12);      // never more than the step's depth
  o.leg_reach = 0;                                         // reach unknown: no lowering
  EXPECT_EQ(StepDownDrop(o, depth, reach_xy), 0.0);

  // in the timeline: the CoM's ground at the landing of a step down is that far below the stance
  Gait g;
  o.leg_reach = 0.70;
  g.Start(0, Stance(), o);
  Footstep s;
  s.foot = kRight;
  s.p = Eigen::Vector3d(0.32, -0.08, -depth);
  g.Replace(0, {s});
  GaitState st;
  g.At(o.start_delay + o.start_time + (1 - o.double_support_ratio) * o.step_time - 1e-6, &st);
  EXPECT_NEAR(st.zmp.z(), -StepDownDrop(o, depth, std::hypot(0.32, 0.16)), 1e-6);
  // off the step the swing foot stays at the top past the nose, then comes down vertically
  const double t_lift = o.start_delay + o.start_time;
  const double t_fall = t_lift + 0.69 * (1 - o.double_support_ratio) * o.step_time;
  g.At(t_fall, &st);
  EXPECT_NEAR(st.feet.p[kRight].z(), o.step_height, 1e-9);
  EXPECT_NEAR(st.feet.p[kRight].x(), 0.32, 1e-3);
  EXPECT_NEAR(st.feet.pitch[kRight], 0.0, 1e-3);  // level again over the lower stair

  // with the sole's size known the foot leaving the upper stair lifts its heel first: toes down
  // (at most asin(apex / half length)), the toe never below the upper stair while over it
  o.sole_half_length = 0.125;
  Gait h;
  h.Start(0, Stance(), o);
  h.Replace(0, {s});
  const double swing = (1 - o.double_support_ratio) * o.step_time;
  double most = 0;
  for (double ph = 0; ph <= 1; ph += 0.01) {
    h.At(t_lift + ph * swing, &st);
    const double pitch = st.feet.pitch[kRight];
    most = std::max(most, pitch);
    EXPECT_LE(pitch, std::asin(o.step_height / o.sole_half_length) + 1e-9);
    const double toe_z = st.feet.p[kRight].z() - o.sole_half_length * std::sin(pitch);
    if (st.feet.p[kRight].x() + o.sole_half_length < 0.2) {
      EXPECT_GE(toe_z, -1e-9) << ph;
    }
  }
  EXPECT_GT(most, 0.5 * std::asin(o.step_height / o.sole_half_length));
  h.At(t_lift + swing - 1e-6, &st);
  EXPECT_NEAR(st.feet.pitch[kRight], 0.0, 1e-6);
}


// start_push: a step from standing starts its double support with the ZMP on the swinging
// sole (the right one here) and moves it linearly onto the stance sole (the left) by the
// lift-off; without it the double support starts from the feet's middle
TEST(Gait, StartPushBeginsTheFirstDoubleSupportOnTheSwingingSole) {
  GaitOptions o;
  o.start_push = true;
  Footstep s;
  s.foot = kRight;
  s.p = Eigen::Vector3d(0.1, -0.08, 0);
  const FeetPose feet = Stance();
  const double t0 = o.start_delay, t_lift = o.start_delay + o.start_time;
  GaitState st;
  for (bool push : {true, false}) {
    o.start_push = push;
    Gait g;
    g.Start(0, feet, o);
    g.Replace(0, {s});
    const Eigen::Vector2d from = push ? Eigen::Vector2d(feet.p[kRight].head<2>())
                                      : Eigen::Vector2d(0.5 * (feet.p[0] + feet.p[1]).head<2>());
    const Eigen::Vector2d to = feet.p[kLeft].head<2>();
    g.At(t0 + 1e-9, &st);
    EXPECT_LT((st.zmp.head<2>() - from).norm(), 1e-6) << push;
    g.At(0.5 * (t0 + t_lift), &st);
    EXPECT_LT((st.zmp.head<2>() - 0.5 * (from + to)).norm(), 1e-6) << push;
    g.At(t_lift, &st);
    EXPECT_LT((st.zmp.head<2>() - to).norm(), 1e-6) << push;
    g.At(t0 - 1e-3, &st);  // standing before: the middle either way
    EXPECT_LT((st.zmp.head<2>() - 0.5 * (feet.p[0] + feet.p[1]).head<2>()).norm(), 1e-6) << push;
  }
}

}  // namespace
}  // namespace ohrp::walking
