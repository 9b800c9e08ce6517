// The guard's braking check on a simulated HRP-1S (sim::InProcessRobot, lock-step, standing
// half-sitting): the right arm driven into the right thigh at increasing speeds and by a jump
// (the reference set at once to a posture inside the thigh), the guard between the commands and
// the robot. Judged on the SIMULATED joint angles with the checker, every pair of a right-arm
// link with a right-leg or waist link: the closest approach stays at or above the file's margin
// less the guard's tolerance. Without the guard (same motions) the hand goes into the thigh.
// Then, from the hold, a command moving the arm away is let through.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "collision/self_collision.h"
#include "controllers/self_collision_guard.h"
#include "in_process_run.h"

namespace ohrp::controllers {
namespace {

const std::string kFile = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
constexpr int kShoulderR = 7, kElbow = 9;  // HRP-1S's right arm
constexpr double kInward = 0.2618, kStraight = 0.0;  // the hand in the thigh [rad]

struct Outcome {
  double closest = INFINITY;  // [m] right arm against right leg and waist, simulated
  uint64_t holds = 0;
  long uncertified = 0;
  double final_shoulder = 0;  // [rad] simulated at the end
};

// the pairs judged: a right-arm link with a right-leg or waist link
std::vector<collision::LinkPair> JudgedPairs(const collision::RobotGeometry& g) {
  std::vector<collision::LinkPair> pairs;
  for (int a = 0; a < static_cast<int>(g.links.size()); ++a)
    for (int b = 0; b < static_cast<int>(g.links.size()); ++b)
      if (g.links[a].name.rfind("RARM_", 0) == 0 &&
          (g.links[b].name.rfind("RLEG_", 0) == 0 || g.links[b].name.rfind("WAIST", 0) == 0))
        pairs.push_back({std::min(a, b), std::max(a, b)});
  return pairs;
}

// `speed` [rad/s]: the arm's references move to the inside posture at that speed (q_ref and
// dq_ref consistent); 0: a jump (the references set there at once). `guarded`: the guard
// filters the commands. 1.5 s of simulated time.
Outcome RunMotion(double speed, bool guarded, double away_after = -1) {
  std::string error;
  auto robot = sim::InProcessRobot::Create(testing::Hrp1sStanding(), &error);
  EXPECT_TRUE(robot) << error;
  Outcome o;
  if (!robot) return o;
  SelfCollisionGuard guard;
  EXPECT_EQ(guard.Configure(kFile, robot->header()), "");
  guard.Activate(robot->sensors());
  const auto& g = guard.file().robot;
  auto checker = collision::SelfCollision::Create(g, &error);
  const auto pairs = JudgedPairs(g);
  const shm::CommandBlock hold = testing::HoldWhereItIs(*robot);
  const double s0 = hold.joint[kShoulderR].q_ref, e0 = hold.joint[kElbow].q_ref;
  const double period = robot->header().control_period;
  std::vector<double> q(robot->header().njoint);
  for (double t = 0; t < 1.5; t += period) {
    shm::CommandBlock c = hold;
    // the references: from the start posture towards the inside one
    double fraction = 1;
    if (speed > 0) fraction = std::min(1.0, t * speed / std::abs(kInward - s0));
    const double vel = speed > 0 && fraction < 1 ? speed : 0;
    c.joint[kShoulderR].q_ref = s0 + fraction * (kInward - s0);
    c.joint[kShoulderR].dq_ref = vel;
    c.joint[kElbow].q_ref = e0 + fraction * (kStraight - e0);
    c.joint[kElbow].dq_ref = vel * (kStraight - e0) / std::abs(kInward - s0);
    if (away_after >= 0 && t >= away_after) {  // back out, away from the thigh
      c.joint[kShoulderR].q_ref = s0 - 0.3;
      c.joint[kElbow].q_ref = e0;
      c.joint[kShoulderR].dq_ref = c.joint[kElbow].dq_ref = 0;
    }
    if (guarded) guard.Filter(robot->sensors(), &c);
    robot->Cycle(c);
    for (size_t j = 0; j < q.size(); ++j) q[j] = robot->sensors().q[j];
    checker->SetPose(q);
    o.closest = std::min(o.closest, checker->Check(pairs, 0.05, {}).min_distance);
  }
  o.holds = guard.holds();
  o.uncertified = guard.uncertified_cycles();
  o.final_shoulder = robot->sensors().q[kShoulderR];
  return o;
}

double Floor() {
  collision::SelfCollisionFile f;
  std::string error;
  EXPECT_TRUE(collision::ReadSelfCollisionFile(kFile, &f, &error)) << error;
  return f.margin - std::max(0.5 * f.margin, 1e-3);  // the margin less the guard's tolerance
}

TEST(SelfCollisionBraking, TheArmStopsShortOfTheThighAtEverySpeed) {
  const double floor = Floor();
  for (double speed : {0.5, 1.0, 2.0, 4.0, 0.0}) {
    const Outcome on = RunMotion(speed, true);
    const Outcome off = RunMotion(speed, false);
    std::printf("speed %.1f rad/s%s: closest simulated arm/leg-waist distance guard on %.1f mm "
                "(%llu holds, %ld uncertified cycles), off %.1f mm\n",
                speed, speed == 0 ? " (a jump)" : "", 1e3 * on.closest,
                static_cast<unsigned long long>(on.holds), on.uncertified, 1e3 * off.closest);
    EXPECT_LT(off.closest, 0) << "the motion must collide without the guard";
    EXPECT_GE(on.closest, floor) << "speed " << speed;
    EXPECT_GE(on.holds, 1u);
  }
}

// standing still (the half-sitting keyframe held): never braked
TEST(SelfCollisionBraking, StandingStillIsNeverBraked) {
  std::string error;
  auto robot = sim::InProcessRobot::Create(testing::Hrp1sStanding(), &error);
  ASSERT_TRUE(robot) << error;
  SelfCollisionGuard guard;
  ASSERT_EQ(guard.Configure(kFile, robot->header()), "");
  guard.Activate(robot->sensors());
  const shm::CommandBlock hold = testing::HoldWhereItIs(*robot);
  for (int k = 0; k < 200; ++k) {
    shm::CommandBlock c = hold;
    // cycle 0 only measures (the brake from the measured state: a hold, not an episode)
    EXPECT_EQ(guard.Filter(robot->sensors(), &c), k == 0) << "cycle " << k;
    EXPECT_FALSE(guard.holding()) << "cycle " << k;
    robot->Cycle(c);
  }
  EXPECT_EQ(guard.holds(), 0u);
  EXPECT_EQ(guard.violations(), 0);
}

TEST(SelfCollisionBraking, FromTheHoldMovingAwayIsLetThrough) {
  const Outcome held = RunMotion(1.0, true);
  const Outcome away = RunMotion(1.0, true, 1.0);  // the same, then back out after 1 s
  EXPECT_LT(away.final_shoulder, held.final_shoulder - 0.2)
      << "held at " << held.final_shoulder << " rad, after backing out " << away.final_shoulder;
}

// the runner: a hold is a result. playback's arm into the leg (issue 15's trajectory) ends with
// exit 9 naming the pair; with the check off the same run ends 0
TEST(SelfCollisionBraking, PlaybackHeldIsNotCompleted) {
  testing::InProcessRun run;
  run.io = testing::Hrp1sStanding();
  run.t_end = 3.5;
  const std::string angles = std::string(OHRP_SOURCE_DIR) + "/scenarios/trajectories/arm_into_leg.dat";
  run.args = {testing::Program("playback"), "--angles", angles, "--ramp", "0.5", "--time-scale", "2"};
  const testing::InProcessResult held = testing::RunInProcess("guard_playback", run);
  EXPECT_EQ(held.exit_code, 9) << held.output;
  EXPECT_NE(held.output.find("FAILED: the motion was not completed: self-collision guard braked "
                             "and held"), std::string::npos) << held.output;
  EXPECT_NE(held.output.find("RARM_"), std::string::npos) << held.output;
  run.args.push_back("--no-self-collision");
  const testing::InProcessResult off = testing::RunInProcess("guard_playback_off", run);
  EXPECT_EQ(off.exit_code, 0) << off.output;
}

}  // namespace
}  // namespace ohrp::controllers
