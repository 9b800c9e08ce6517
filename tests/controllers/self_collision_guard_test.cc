// The online self-collision check (controllers/self_collision_guard.h) with HRP-1S's shipped
// file: the braking distance of one joint against closed forms, an arm swinging fast into the
// leg braked along a ramp (the pair reported), one moving away let through, a file for another
// robot or without dynamics refused, and a cycle allocates nothing. The simulated proof is
// self_collision_braking_test.cc.
#include "controllers/self_collision_guard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>

#include "../robot_model/count_allocations.h"
#include "common/scratch.h"
#include "self_collision_guard_fixture.h"

namespace ohrp::controllers::guard_testing {
namespace {

// the motion interval of one joint against closed forms: coasting for the horizon, then
// v^2 / (2 a) to rest; the speed limit caps both
TEST(GuardExcursion, BrakingDistanceOfOneJoint) {
  double lo = 0, hi = 0;
  // 1.2 rad/s, no acceleration, 10 ms (a period and one of latency), 3 rad/s^2 of braking
  SelfCollisionGuard::Excursion(1.2, 0, 0, 0.01, 0, 3.0, &lo, &hi);
  EXPECT_NEAR(hi, 1.2 * 0.01 + 1.2 * 1.2 / (2 * 3.0), 1e-12);
  EXPECT_EQ(lo, 0);
  // accelerating at up to 2 rad/s^2 (down to -1) for 10 ms: v t + a t^2 / 2, then from 0.52
  SelfCollisionGuard::Excursion(0.5, -1, 2, 0.01, 0, 3.0, &lo, &hi);
  EXPECT_NEAR(hi, 0.5 * 0.01 + 0.5 * 2 * 1e-4 + 0.52 * 0.52 / 6, 1e-12);
  EXPECT_EQ(lo, 0);
  // the same at its speed limit 0.5 rad/s: no faster
  SelfCollisionGuard::Excursion(0.5, -1, 2, 0.01, 0.5, 3.0, &lo, &hi);
  EXPECT_NEAR(hi, 0.5 * 0.01 + 0.25 / 6, 1e-12);
  // moving the other way, mirrored
  SelfCollisionGuard::Excursion(-1.2, 0, 0, 0.01, 0, 3.0, &lo, &hi);
  EXPECT_NEAR(lo, -(1.2 * 0.01 + 1.2 * 1.2 / 6), 1e-12);
  EXPECT_EQ(hi, 0);
}

// One hinge of unknown inertia I in [0.01, 2.2] kg m^2 (G1's waist: its rotor alone up to the
// upper body) under a position servo (kp 200 N m/rad, kd 10 N m s/rad, 50 N m limit) commanded
// 0.05 rad ahead against a constant load of 5 N m, from rest: for two periods (8 ms) the servo
// acts, then a ramp at 20 rad/s^2 to rest. The prediction (the acceleration over either end of
// the inertia, narrowed by the servo's damping, then the ramp) must hold the farthest point of
// the motion integrated finely for every inertia, and be within a factor 2 of it; without the
// damping band the rotor alone (5 N m over 0.01 kg m^2) would bound it 5x wider.
TEST(GuardExcursion, OneHingeOfUnknownInertiaAgainstItsIntegratedMotion) {
  const double kp = 200, kd = 10, tau_max = 50, load = 5, lead = 0.05, T = 0.008, decel = 20;
  const double i_min = 0.01, i_max = 2.2;
  double farthest = 0;
  for (double inertia : {0.01, 0.02, 0.05, 0.1, 0.3, 1.0, 2.2}) {
    double q = 0, v = 0;
    const double h = 1e-6;
    for (double t = 0; t < T; t += h) {
      const double tau = std::clamp(kp * (lead - q) - kd * v, -tau_max, tau_max);
      v += h * (tau - load) / inertia;
      q += h * v;
      farthest = std::max(farthest, q);
    }
    farthest = std::max(farthest, q + (v > 0 ? v * v / (2 * decel) : 0.0));
  }
  // the servo's torque at the start (at rest the velocity carries the joint nowhere): kp lead
  const double f = kp * lead - load;
  const double a_lo = std::min(f / i_min, f / i_max), a_hi = std::max(f / i_min, f / i_max);
  double v_floor = std::min(a_lo, 0.0) * T, v_ceil = std::max(a_hi, 0.0) * T;
  shm::JointCommand c{shm::JointMode::kPosition, 0, lead, 0, 0, kp, kd};
  SelfCollisionGuard::VelocityBand(c, 0, 0, load, load, tau_max, T, &v_floor, &v_ceil);
  EXPECT_LT(v_ceil, 2 * f / kd);  // about the damping's equilibrium, not a_hi T = 4 rad/s
  double lo = 0, hi = 0;
  SelfCollisionGuard::Excursion(0, a_lo, a_hi, T, v_floor, v_ceil, decel, &lo, &hi);
  EXPECT_GE(hi, farthest);
  EXPECT_LE(hi, 2 * farthest);
  double hi_wide = 0;
  SelfCollisionGuard::Excursion(0, a_lo, a_hi, T, 0, decel, &lo, &hi_wide);
  EXPECT_GT(hi_wide, 5 * farthest);
}

// the deceleration: the torque limit less the load, over the largest inertia
TEST_F(GuardTest, DecelerationFromTheFile) {
  const collision::JointDynamics& d = file_.dynamics[kRarmShoulderR];
  EXPECT_NEAR(guard_.Deceleration(kRarmShoulderR, 0.0), 200 / d.inertia_max, 1e-12);
  EXPECT_NEAR(guard_.Deceleration(kRarmShoulderR, NAN), (200 - d.gravity_max) / d.inertia_max, 1e-12);
  EXPECT_NEAR(guard_.Deceleration(kRarmShoulderR, 1e6), (200 - d.gravity_max) / d.inertia_max, 1e-12);
}

TEST_F(GuardTest, BrakesAnArmMovingFastIntoTheLegAlongARamp) {
  double q[shm::kMaxJoints] = {};
  Command(q, header_.njoint, &commands_);  // the command holds the zero posture...
  sensors_.dq[kRarmShoulderR] = 2.0;       // ...but the arm swings inwards at 2 rad/s
  guard_.Activate(sensors_);               // (steadily: not accelerating)
  Measure(&guard_);
  EXPECT_TRUE(guard_.Filter(sensors_, &commands_));
  EXPECT_TRUE(guard_.holding());
  EXPECT_EQ(guard_.holds(), 1u);
  // not a frozen reference: the velocity ramped down by one period's braking, the position
  // advanced consistently
  const double v1 = commands_.joint[kRarmShoulderR].dq_ref;
  EXPECT_GT(v1, 0.0);
  EXPECT_LT(v1, 2.0);
  EXPECT_NEAR(commands_.joint[kRarmShoulderR].q_ref, 0.5 * (2.0 + v1) * 0.005, 1e-12);
  EXPECT_GT(guard_.hold_pair().a, -1);
  std::ostringstream out;
  guard_.Report("test", out);
  EXPECT_NE(out.str().find("braked and held in 1 cycles (1 holds)"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("RARM_"), std::string::npos) << out.str();
  // the same swing outwards, away from the leg: let through
  SelfCollisionGuard g;
  ASSERT_EQ(g.Configure(kFile, header_), "");
  sensors_.dq[kRarmShoulderR] = -2.0;
  g.Activate(sensors_);
  q[kRarmShoulderR] = -0.5;
  Command(q, header_.njoint, &commands_);
  Measure(&g);
  EXPECT_FALSE(g.Filter(sensors_, &commands_));
  EXPECT_EQ(g.holds(), 0u);
}

// Only the chain of the pair it cannot certify is braked (the joints between its two links and
// their common ancestor): the right arm swinging into the right leg brakes the right arm and the
// torso above it (WAIST_P, WAIST_R, CHEST carry the arm), while the left arm, on no chain of an
// uncertified pair, keeps following its command (issue 29: a hold during a walk braked
// balance's torso too, for pairs it does not move).
TEST_F(GuardTest, BrakesOnlyTheChainOfTheUncertifiedPair) {
  constexpr int kLarmShoulderR = 20, kWaistP = 26, kChest = 28;
  double q[shm::kMaxJoints] = {};
  q[kLarmShoulderR] = 0.3;  // the left arm moves outwards, away from everything
  q[kWaistP] = 0.01;        // the torso is commanded to pitch a little
  Command(q, header_.njoint, &commands_);
  sensors_.dq[kRarmShoulderR] = 2.0;  // the right arm swings inwards, into the right leg
  guard_.Activate(sensors_);
  Measure(&guard_);
  ASSERT_TRUE(guard_.Filter(sensors_, &commands_));
  ASSERT_TRUE(guard_.holding());
  const std::string a = file_.robot.links[guard_.hold_pair().a].name,
                    b = file_.robot.links[guard_.hold_pair().b].name;
  EXPECT_TRUE(a.rfind("RARM_", 0) == 0 || b.rfind("RARM_", 0) == 0) << a << " / " << b;
  // the right arm is braked along its ramp
  EXPECT_LT(commands_.joint[kRarmShoulderR].dq_ref, 2.0);
  EXPECT_GT(commands_.joint[kRarmShoulderR].q_ref, 0.0);
  // the left arm is on no uncertified pair's chain: its command passes unchanged
  EXPECT_EQ(commands_.joint[kLarmShoulderR].q_ref, 0.3);
  EXPECT_EQ(commands_.joint[kLarmShoulderR].tau_ff, 0.0);
  // the torso carries the right arm against the leg: braked (from rest: held where it stands)
  EXPECT_EQ(commands_.joint[kWaistP].q_ref, 0.0);  // not the commanded 0.01
  EXPECT_EQ(commands_.joint[kChest].dq_ref, 0.0);
  // the legs are loaded (no force sensor in this header): never braked
  EXPECT_EQ(guard_.leg_brake_cycles(), 0);
}

// the brake commands its ramp's deceleration as a feed-forward torque on top of the
// controller's own (the period's mean deceleration at the joint's SMALLEST inertia: the largest
// one's torque reversed G1's light rotors within a period): a servo that must first build a
// tracking error lets the joint coast past the ramp's end (the arm_jump_past_thigh trial:
// 0.044 rad at the shoulder, the hand 0.4 mm from the thigh)
TEST_F(GuardTest, TheBrakeFeedsItsDecelerationForward) {
  double q[shm::kMaxJoints] = {};
  Command(q, header_.njoint, &commands_);
  for (int j = 0; j < header_.njoint; ++j) commands_.joint[j].tau_ff = 3.0;  // the controller's
  sensors_.dq[kRarmShoulderR] = 2.0;  // swinging inwards, into the leg
  guard_.Activate(sensors_);
  Measure(&guard_);
  ASSERT_TRUE(guard_.Filter(sensors_, &commands_));
  const shm::JointCommand& c = commands_.joint[kRarmShoulderR];
  const double decel = (2.0 - c.dq_ref) / 0.005;  // the ramp's, this period
  ASSERT_GT(decel, 0.0);
  const double inertia = file_.dynamics[kRarmShoulderR].inertia_min;
  EXPECT_NEAR(c.tau_ff, 3.0 - decel * inertia, 1e-9);
  EXPECT_EQ(commands_.joint[kRarmShoulderR + 1].tau_ff, 3.0);  // a joint at rest: its own
}

TEST_F(GuardTest, LetsSafeMotionAndMovingAwayThrough) {
  double q[shm::kMaxJoints] = {};
  q[kRarmShoulderR] = -0.5;  // outwards
  Command(q, header_.njoint, &commands_);
  EXPECT_FALSE(guard_.Filter(sensors_, &commands_));
  EXPECT_EQ(commands_.joint[kRarmShoulderR].q_ref, -0.5);
  EXPECT_EQ(guard_.held_cycles(), 0);
  std::ostringstream out;
  guard_.Report("test", out);
  EXPECT_EQ(out.str(), "");
}

TEST_F(GuardTest, RefusesAFileForAnotherRobot) {
  shm::SegmentHeader other = header_;
  other.model_hash ^= 1;
  SelfCollisionGuard g;
  EXPECT_NE(g.Configure(kFile, other).find("regenerate it with ohrp_selfcollision"), std::string::npos);
  std::string robot;
  // another hash, the same joints: this robot's model changed (regenerate); other joints and
  // another name: another robot
  EXPECT_EQ(SelfCollisionGuard::FileOwner(kFile, other, &robot), SelfCollisionGuard::Owner::kThisRobot);
  EXPECT_EQ(robot, "hrp1s");
  std::strcpy(other.robot_name, "elsewhere");
  EXPECT_EQ(SelfCollisionGuard::FileOwner(kFile, other, &robot), SelfCollisionGuard::Owner::kThisRobot);
  std::strcpy(other.joint_names[0], "ELSEWHERE");
  EXPECT_EQ(SelfCollisionGuard::FileOwner(kFile, other, &robot), SelfCollisionGuard::Owner::kAnotherRobot);
  std::strcpy(other.robot_name, "hrp1s");
  EXPECT_EQ(SelfCollisionGuard::FileOwner(kFile, other, &robot), SelfCollisionGuard::Owner::kThisRobot);
  EXPECT_EQ(SelfCollisionGuard::FileOwner(kFile, header_, &robot), SelfCollisionGuard::Owner::kThisModel);
  other = header_;
  std::strcpy(other.joint_names[3], "ELSEWHERE");
  EXPECT_NE(g.Configure(kFile, other).find("joint 3 is RLEG_KNEE, the segment's is ELSEWHERE"),
            std::string::npos);
}

// a file without the joints' dynamics: refused, never guessed
TEST_F(GuardTest, RefusesAFileWithoutDynamics) {
  collision::SelfCollisionFile f = file_;
  f.dynamics.clear();
  const std::string path = ohrp::testing::ScratchFile("no_dynamics", collision::SelfCollisionYaml(f), ".yaml");
  SelfCollisionGuard g;
  const std::string problem = g.Configure(path, header_);
  EXPECT_NE(problem.find("has no dynamics: section"), std::string::npos) << problem;
  EXPECT_NE(problem.find("regenerate it with ohrp_selfcollision"), std::string::npos) << problem;
}

#ifdef OHRP_CAN_COUNT
TEST_F(GuardTest, ACycleAllocatesNothing) {
  double q[shm::kMaxJoints] = {};
  q[kRarmShoulderR] = 0.2618;
  q[0] = 0.7;  // a leg out of nothing's way, the arm into the leg: both paths of the check
  Command(q, header_.njoint, &commands_);
  sensors_.dq[kRarmShoulderR] = 2.0;  // fast into the leg: the bisection and the brake
  EXPECT_EQ(ohrp::testing::Allocations([&] { guard_.Filter(sensors_, &commands_); }), 0);
  EXPECT_TRUE(guard_.holding());
  sensors_.dq[kRarmShoulderR] = 0.0;
  q[kRarmShoulderR] = -0.3;
  Command(q, header_.njoint, &commands_);
  EXPECT_EQ(ohrp::testing::Allocations([&] { guard_.Filter(sensors_, &commands_); }), 0);
}

TEST_F(LegGuardTest, BrakingALegAllocatesNothing) {
  Feet(0.0);
  SelfCollisionGuard g;
  ASSERT_TRUE(Swing(&g));
  EXPECT_EQ(ohrp::testing::Allocations([&] {
              for (double fz : {0.0, 5 * on_, 0.0}) {  // braked, released, braked again
                Feet(fz);
                g.Filter(sensors_, &commands_);
              }
            }), 0);
  EXPECT_TRUE(g.holding());
}
#endif

}  // namespace
}  // namespace ohrp::controllers::guard_testing
