// Tests the standing stabilizer's laws (controllers/stabilizer.h) against closed forms: the ZMP
// of known wrenches, the DCM law on an ideal linear inverted pendulum, the damping control's
// first-order response, and the direction of the hip strategy.
#include "controllers/stabilizer.h"
#include "controllers/hip_strategy.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

namespace ohrp::controllers {
namespace {

constexpr double kG = 9.81;

// the wrench at a sensor p_S of a force f applied at a point a on the ground
FootWrench WrenchAt(const Eigen::Vector3d& p_S, const Eigen::Vector3d& a, const Eigen::Vector3d& f) {
  FootWrench w;
  w.p_WS = p_S;
  w.f_W = f;
  w.n_W = (a - p_S).cross(f);
  return w;
}

Support TwoSoles() {
  Support s;
  s.centre[0] = Eigen::Vector2d(0.05, 0.09);
  s.centre[1] = Eigen::Vector2d(0.05, -0.09);
  s.half_size[0] = s.half_size[1] = Eigen::Vector2d(0.125, 0.07);
  s.ground_z = 0;
  return s;
}

TEST(MeasureZmp, RecoversTheCentreOfPressureOfKnownForces) {
  // two forces with horizontal parts, sensors 7 cm above their feet: the ZMP is the
  // force-weighted mean of the application points (tolerance: rounding)
  const Eigen::Vector3d a0(0.10, 0.12, 0), a1(-0.02, -0.08, 0);
  const Eigen::Vector3d f0(15, -4, 500), f1(-3, 7, 700);
  FootWrench w[2] = {WrenchAt({0, 0.09, 0.07}, a0, f0), WrenchAt({0, -0.09, 0.07}, a1, f1)};
  Eigen::Vector2d p;
  ASSERT_TRUE(MeasureZmp(w, 2, 0.0, 10.0, &p));
  const Eigen::Vector2d expected = (a0.head<2>() * f0.z() + a1.head<2>() * f1.z()) / (f0.z() + f1.z());
  EXPECT_NEAR(p.x(), expected.x(), 1e-12);
  EXPECT_NEAR(p.y(), expected.y(), 1e-12);
}

TEST(MeasureZmp, RefusesAnUnloadedRobot) {
  FootWrench w[2];
  Eigen::Vector2d p(7, 7);
  EXPECT_FALSE(MeasureZmp(w, 2, 0.0, 10.0, &p));
  EXPECT_EQ(p.x(), 7);
}

TEST(Stabilizer, DcmConvergesAtItsRateOnAnIdealPendulum) {
  // LIPM x'' = w^2 (x - p) with p = the desired ZMP (ideal tracking, never clamped here):
  // xi - c_ref decays as exp(-k t). Tolerance: the explicit 1 ms integration (0.5 %).
  StabilizerGains g;
  g.k_dcm = 3.0;
  g.hip_strategy = false;
  Stabilizer st(g);
  const double h = 0.8, w = std::sqrt(kG / h), dt = 1e-4;
  StabilizerInput in;
  in.support = TwoSoles();
  in.mass = 100;
  in.c_ref = Eigen::Vector2d(0.05, 0.0);
  Eigen::Vector2d x(0.07, 0.01), v(0.05, -0.02);
  const Eigen::Vector2d xi0 = x + v / w - in.c_ref;
  for (int i = 0; i < 10000; ++i) {  // 1 s
    in.c = Eigen::Vector3d(x.x(), x.y(), h);
    in.dc = Eigen::Vector3d(v.x(), v.y(), 0);
    const StabilizerOutput& out = st.Update(in, dt);
    ASSERT_TRUE((out.zmp_desired - out.zmp_desired_raw).norm() < 1e-12) << "clamped at step " << i;
    const Eigen::Vector2d a = w * w * (x - out.zmp_desired);
    x += dt * v + 0.5 * dt * dt * a;
    v += dt * a;
  }
  const Eigen::Vector2d xi1 = x + v / w - in.c_ref;
  EXPECT_NEAR(xi1.x(), xi0.x() * std::exp(-3.0), 0.005 * std::abs(xi0.x()));
  EXPECT_NEAR(xi1.y(), xi0.y() * std::exp(-3.0), 0.005 * std::abs(xi0.y()));
}

TEST(Stabilizer, DesiredZmpIsClampedToTheSoles) {
  StabilizerGains g;
  g.support_margin = 0.01;
  Stabilizer st(g);
  StabilizerInput in;
  in.support = TwoSoles();
  in.mass = 100;
  in.c = Eigen::Vector3d(0.05, 0, 0.8);
  in.dc = Eigen::Vector3d(2.0, -2.0, 0);  // falling fast to the front right
  const StabilizerOutput& out = st.Update(in, 0.005);
  EXPECT_NEAR(out.zmp_desired.x(), 0.05 + 0.125 - 0.01, 1e-12);
  EXPECT_NEAR(out.zmp_desired.y(), -0.09 - 0.07 + 0.01, 1e-12);
  EXPECT_GT(out.zmp_desired_raw.x(), out.zmp_desired.x());
}

TEST(Stabilizer, FootDampingControlSettlesAtTheClosedFormOffset) {
  // a constant pitch moment error e: theta' = e / D - theta / T settles at e T / D, and after
  // one time constant it is at (1 - 1/e) of that (explicit Euler at dt = T/1000: 0.1 %)
  StabilizerGains g;
  g.hip_strategy = false;
  g.ankle_damping = 200;
  g.ankle_recovery = 0.5;
  Stabilizer st(g);
  StabilizerInput in;
  in.support = TwoSoles();
  in.mass = 100;
  in.c = Eigen::Vector3d(0.05, 0, 0.8);  // at c_ref, still: desired ZMP at the CoM
  in.c_ref = Eigen::Vector2d(0.05, 0);
  const double fz = 0.5 * in.mass * kG;
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector3d p_S(0.0, in.support.centre[i].y(), 0.07);
    // each foot's CoP at the desired (x = 0.05, its centre) plus a pitch moment error of 20 N m
    in.feet[i] = WrenchAt(p_S, {0.05, in.support.centre[i].y(), 0}, {0, 0, fz});
    in.feet[i].n_W.y() += 20.0;
  }
  const double dt = 0.0005;
  for (int i = 0; i < 1000; ++i) st.Update(in, dt);  // one time constant
  const double steady = 20.0 * g.ankle_recovery / g.ankle_damping;
  EXPECT_NEAR(st.output().foot_pitch[0], steady * (1 - std::exp(-1.0)), 0.001 * steady);
  EXPECT_NEAR(st.output().foot_pitch[1], steady * (1 - std::exp(-1.0)), 0.001 * steady);
  EXPECT_NEAR(st.output().foot_roll[0], 0.0, 1e-9);
  EXPECT_NEAR(st.output().dz, 0.0, 1e-12);  // equal loads as desired
}

TEST(Stabilizer, HeavierLeftFootRaisesTheLeftSole) {
  StabilizerGains g;
  g.hip_strategy = false;
  Stabilizer st(g);
  StabilizerInput in;
  in.support = TwoSoles();
  in.mass = 100;
  in.c = Eigen::Vector3d(0.05, 0, 0.8);
  in.c_ref = Eigen::Vector2d(0.05, 0);
  in.feet[0] = WrenchAt({0.0, 0.09, 0.07}, {0.05, 0.09, 0}, {0, 0, 600});
  in.feet[1] = WrenchAt({0.0, -0.09, 0.07}, {0.05, -0.09, 0}, {0, 0, 381});
  for (int i = 0; i < 100; ++i) st.Update(in, 0.005);
  EXPECT_GT(st.output().dz, 0.0);
  EXPECT_NEAR(st.output().fz_share[0], 0.5, 1e-12);
}

TEST(Stabilizer, HipStrategyLeansTheTorsoIntoAForwardFall) {
  // a forward fall beyond the toes needs L_dot_y > 0: the torso pitches forward (+y); a fall to
  // the left (+y) needs L_dot_x < 0: the torso rolls about -x
  for (int dir = 0; dir < 2; ++dir) {
    Stabilizer st;
    StabilizerInput in;
    in.support = TwoSoles();
    in.mass = 100;
    in.c = Eigen::Vector3d(0.05, 0, 0.8);
    in.c_ref = Eigen::Vector2d(0.05, 0);
    in.dc = dir == 0 ? Eigen::Vector3d(1.5, 0, 0) : Eigen::Vector3d(0, 1.5, 0);
    for (int i = 0; i < 10; ++i) st.Update(in, 0.005);
    if (dir == 0) {
      EXPECT_GT(st.output().torso_pitch, 0.0);
      EXPECT_NEAR(st.output().torso_roll, 0.0, 1e-12);
    } else {
      EXPECT_LT(st.output().torso_roll, 0.0);
      EXPECT_NEAR(st.output().torso_pitch, 0.0, 1e-12);
    }
  }
}

// issue 31: the hip strategy's share and clamp from the robot (hip_strategy.h), against the
// closed forms on made-up torsos
TEST(HipStrategy, ClampIsTwoThirdsOfTheTravelUnlessTheLeanMovesTheCoMTooFar) {
  TorsoAxis a;
  a.inertia = 5.0;
  a.moment = 10.0;  // lever 10 / 100 = 0.1 m
  a.travel = 0.6;
  a.tau_max = 1e4;
  // a wide sole: asin(0.5 * 0.5 / 0.1) undefined (the lean never reaches it): the travel's 2/3
  EXPECT_NEAR(DeriveHipAxis(a, 100.0, 0.5).max_angle, 0.4, 1e-12);
  // a 6 cm wide sole: sin(theta) 0.1 = 0.5 * 0.03
  EXPECT_NEAR(DeriveHipAxis(a, 100.0, 0.03).max_angle, std::asin(0.15), 1e-12);
}

TEST(HipStrategy, ShareIsTheTorqueLeftAtTheClampOverTheMomentOfASolesHalfSize) {
  TorsoAxis a;
  a.inertia = 2.0;
  a.moment = 4.0;
  a.travel = 0.45;  // clamp 0.3 (the lean's own bound, asin(0.05 / 0.08) = 0.68, is wider)
  a.tau_max = 1e4;
  EXPECT_NEAR(DeriveHipAxis(a, 50.0, 0.1).gain, 1.0, 1e-12);  // a strong joint
  a.tau_max = 20.0;
  const HipAxisLimits l = DeriveHipAxis(a, 50.0, 0.1);
  EXPECT_NEAR(l.max_angle, 0.3, 1e-12);
  EXPECT_NEAR(l.gain, (20.0 - kG * 4.0 * std::sin(0.3)) / (50.0 * kG * 0.1), 1e-12);
}

TEST(Stabilizer, HipStrategySettlesAtItsClosedFormLeanPerAxis) {
  // a constant lateral and forward excess: each offset settles at share m g e / (I w0^2), each
  // axis with its own inertia and share
  StabilizerGains g;
  g.ankle_strategy = false;
  g.k_dcm = 0;
  g.torso_inertia[0] = 3.0;
  g.torso_inertia[1] = 5.0;
  g.torso_share[0] = 0.5;
  g.torso_share[1] = 0.8;
  g.torso_limit[0] = g.torso_limit[1] = 1.0;
  Stabilizer st(g);
  StabilizerInput in;
  in.mass = 60;
  in.support = TwoSoles();
  // the CoM beyond the front-left corner of the support, still: the excess is fixed
  in.c = Eigen::Vector3d(0.05 + 0.125 - 0.015 + 0.004, 0.09 + 0.07 - 0.015 + 0.003, 0.8);
  in.c_ref = in.c.head<2>();
  for (int i = 0; i < 2; ++i) in.feet[i].f_W.z() = 0.5 * in.mass * kG;
  for (int k = 0; k < 5000; ++k) st.Update(in, 0.002);
  const double w0 = g.hip_return;
  EXPECT_NEAR(st.output().torso_pitch, 0.5 * 60 * kG * 0.004 / (3.0 * w0 * w0), 1e-6);
  EXPECT_NEAR(st.output().torso_roll, -0.8 * 60 * kG * 0.003 / (5.0 * w0 * w0), 1e-6);
}

}  // namespace
}  // namespace ohrp::controllers
