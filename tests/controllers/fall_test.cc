// Issue 28, item 1 on the controller side: a controller detects a fall from its own sensors
// (controllers/fall_watch.h, run by the runner for every program) and ends with exit 8 saying
// when and why; balance never says "stood" after a fall. The built programs run against an
// in-process HRP-1S (in_process_run.h) that the test makes fall: its joints limp (the commands'
// gains zeroed) or a push far beyond what balance can take. And the watch itself, fed the
// simulated robot's sensor blocks: quiet while the robot stands, firing on a limp robot within
// a bounded time, with the cause.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "controllers/fall_watch.h"
#include "common/scratch.h"
#include "controllers/runner.h"
#include "in_process_run.h"

namespace ohrp::controllers::testing {
namespace {

constexpr double kLimpAt = 1.5;  // [s] producer time

void Limp(double t, shm::CommandBlock* c) {
  if (t < kLimpAt) return;
  for (int j = 0; j < c->njoint; ++j) c->joint[j].kp = c->joint[j].kd = 0;
}

// "the robot fell at t = T s" in `out`: T, or -1 when absent
double FallTime(const std::string& out) {
  std::smatch m;
  static const std::regex re("the robot fell at t = ([0-9.]+) s \\(cycle [0-9]+\\)");
  return std::regex_search(out, m, re) ? std::stod(m[1]) : -1.0;
}

TEST(FallWatch, QuietWhileStandingFiresWhenLimpWithTheCause) {
  std::string error;
  auto robot = sim::InProcessRobot::Create(Hrp1sStanding(), &error);
  ASSERT_TRUE(robot) << error;
  FallWatch watch;
  EXPECT_EQ(watch.Configure(robot->header(), DefaultFallLimits()), "");
  // the keyframe's pose held: 2 s standing, never a fall; the feet carry the weight (armed)
  shm::CommandBlock hold = HoldWhereItIs(*robot);
  while (robot->sensors().time < 2.0) {
    ASSERT_FALSE(watch.Update(robot->sensors(), Controller::kNoTilt)) << watch.Describe();
    robot->Cycle(hold);
  }
  EXPECT_TRUE(watch.armed());
  // limp: the robot collapses; the watch fires within 3 s, after the limits' persistence
  for (int j = 0; j < hold.njoint; ++j) hold.joint[j].kp = hold.joint[j].kd = 0;
  const double limp = robot->sensors().time;
  while (!watch.Update(robot->sensors(), Controller::kNoTilt) && robot->sensors().time < limp + 3)
    robot->Cycle(hold);
  ASSERT_TRUE(watch.fallen()) << "base z " << robot->sensors().sim_truth.p_WB[2];
  const FallEvent& e = watch.event();
  EXPECT_GT(e.time, limp);
  EXPECT_GE(e.time - e.since, e.cause == FallCause::kTilt ? watch.limits().tilt_time
                                                          : watch.limits().unloaded_time);
  EXPECT_EQ(e.cycle, robot->sensors().cycle);
  // the truth agrees: the base is well below its standing height (0.68 m)
  EXPECT_LT(robot->sensors().sim_truth.p_WB[2], 0.5);
  EXPECT_NE(watch.Describe().find("the robot fell at t = "), std::string::npos);
  std::printf("[ figures  ] limp at %.3f s: fall watch fired at %.3f s (%s, since %.3f s), "
              "base z %.3f m\n",
              limp, e.time, FallCauseName(e.cause), e.since, robot->sensors().sim_truth.p_WB[2]);
}

// the tilt's message names what the tilt is measured from: upright, unless the controller says
// otherwise (Controller::tilt_reference: walk's rolling pelvis, its commanded orientation)
TEST(FallWatch, TheTiltMessageNamesWhatTheTiltIsMeasuredFrom) {
  std::string error;
  auto robot = sim::InProcessRobot::Create(Hrp1sStanding(), &error);
  ASSERT_TRUE(robot) << error;
  FallWatch watch;
  ASSERT_EQ(watch.Configure(robot->header(), DefaultFallLimits()), "");
  // the standing robot's block (its feet loaded: armed) with the controller's estimate at twice
  // the limit, held over the limit's time
  shm::SensorBlock s = robot->sensors();
  const double tilt = 2 * watch.limits().max_tilt;
  for (int i = 0; i < 4000 && !watch.Update(s, tilt); ++i) {
    s.time += 0.005;
    ++s.cycle;
  }
  ASSERT_TRUE(watch.fallen());
  ASSERT_EQ(watch.event().cause, FallCause::kTilt) << watch.Describe();
  EXPECT_NE(watch.Describe().find(" deg from upright, beyond"), std::string::npos) << watch.Describe();
  const std::string rolled = watch.Describe("its commanded orientation");
  EXPECT_NE(rolled.find(" deg from its commanded orientation, beyond"), std::string::npos) << rolled;
  EXPECT_EQ(rolled.find("upright"), std::string::npos) << rolled;
}

TEST(FallWatch, LimitsFromTheModelNarrowTheDefaults) {
  // a CoM 0.7 m over soles reaching 0.11 m: tipping at atan(0.11 / 0.7) = 8.9 deg
  const FallLimits l = FallLimitsFor(0.7, 0.11, 0.0);
  EXPECT_NEAR(l.max_tilt, 2 * std::atan2(0.11, 0.7), 1e-12);
  EXPECT_NEAR(l.tilt_time, std::sqrt(0.7 / 9.81), 1e-12);
  EXPECT_NEAR(l.unloaded_time, 2 * std::sqrt(0.7 / 9.81), 1e-12);
  EXPECT_LT(l.max_tilt, DefaultFallLimits().max_tilt);
  // nonsense in: the defaults out
  EXPECT_EQ(FallLimitsFor(NAN, 0.1, 0).max_tilt, DefaultFallLimits().max_tilt);
}

TEST(FallPrograms, PostureOnALimpRobotExitsEightWithTimeAndCause) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.args = {Program("posture"), "--ramp", "0.5", "--no-self-collision"};
  run.t_end = 8.0;
  run.edit_commands = Limp;
  const InProcessResult r = RunInProcess("fall_posture", run);
  EXPECT_EQ(r.exit_code, kExitFell) << r.output;
  EXPECT_TRUE(r.left_early) << r.output;
  const double t = FallTime(r.output);
  EXPECT_GT(t, kLimpAt) << r.output;
  EXPECT_LT(t, kLimpAt + 3.0) << r.output;
  EXPECT_TRUE(r.output.find("tilted") != std::string::npos ||
              r.output.find("feet carry") != std::string::npos)
      << r.output;
  std::printf("[ figures  ] posture limp at %.1f s: exit %d, fall at %.3f s, base z %.3f m\n",
              kLimpAt, r.exit_code, t, r.base_z);
}

// the producer's verdict: sim_host's fall watch marks every block from the fall on
// (status::kFallen); a program whose own watch saw nothing (here the robot stands: the mark is
// the test's) still ends with exit 8, saying that the producer judged a fall
TEST(FallPrograms, AFallTheProducerJudgedEndsTheProgramWithEight) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.args = {Program("posture"), "--ramp", "0.5", "--no-self-collision"};
  run.t_end = 2.5;
  run.edit_sensors = [](shm::SensorBlock* s) {
    if (s->time >= 2.0) s->status |= shm::status::kFallen;
  };
  const InProcessResult r = RunInProcess("fall_producer", run);
  EXPECT_EQ(r.exit_code, kExitFell) << r.output;
  EXPECT_FALSE(r.left_early) << r.output;
  EXPECT_NE(r.output.find("ended its run: the robot fell (the producer's fall watch"),
            std::string::npos)
      << r.output;
  // without the mark the same run is a clean end
  run.edit_sensors = nullptr;
  const InProcessResult clean = RunInProcess("fall_producer_none", run);
  EXPECT_EQ(clean.exit_code, 0) << clean.output;
}

TEST(FallPrograms, BalancePushedOverExitsEightAndNeverSaysStood) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  sim::Perturbation push;  // 300 N s forward over 0.1 s at 4 s, once standing
  push.t0 = 4.0;
  push.t1 = 4.1;
  push.force[0] = 3000;
  run.io.pushes.push_back(push);
  run.args = {Program("balance"), "--ramp", "0.5", "--no-self-collision"};
  run.t_end = 9.0;
  const InProcessResult r = RunInProcess("fall_balance", run);
  EXPECT_EQ(r.exit_code, kExitFell) << r.output;
  const double t = FallTime(r.output);
  EXPECT_GT(t, push.t0) << r.output;
  EXPECT_LT(t, push.t0 + 3.0) << r.output;
  EXPECT_EQ(r.output.find("balance: stood"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("balance: did NOT keep the robot standing: it fell"), std::string::npos)
      << r.output;
  std::printf("[ figures  ] balance pushed 300 N s at %.1f s: exit %d, fall at %.3f s\n%s",
              push.t0, r.exit_code, t, r.output.c_str());
}

// the watch's limits against the pushes balance survives: 70 N s forward (it stands after
// 73.4 N s, docs/balance.md) and 90 N s to the left (96.9): no fall, "stood"
TEST(FallPrograms, APushBalanceSurvivesIsNoFall) {
  for (const double angle : {0.0, 90.0}) {
    InProcessRun run;
    run.io = Hrp1sStanding();
    sim::Perturbation push;
    push.t0 = 4.0;
    push.t1 = 4.1;
    const double impulse = angle == 0 ? 70 : 90;
    push.force[0] = impulse / 0.1 * std::cos(angle * M_PI / 180);
    push.force[1] = impulse / 0.1 * std::sin(angle * M_PI / 180);
    run.io.pushes.push_back(push);
    run.args = {Program("balance"), "--ramp", "0.5", "--no-self-collision"};
    run.t_end = 7.0;
    const InProcessResult r = RunInProcess("fall_balance_survived", run);
    EXPECT_EQ(r.exit_code, kExitOk) << angle << " deg: " << r.output;
    EXPECT_FALSE(r.left_early) << r.output;
    EXPECT_NE(r.output.find("balance: stood"), std::string::npos) << r.output;
    EXPECT_GT(r.base_z, 0.6) << r.output;  // the truth: still standing
  }
}

TEST(FallPrograms, BalanceStandingQuietlyIsNoFall) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.args = {Program("balance"), "--ramp", "0.5", "--no-self-collision"};
  run.t_end = 4.5;
  const InProcessResult r = RunInProcess("fall_balance_quiet", run);
  EXPECT_EQ(r.exit_code, kExitOk) << r.output;
  EXPECT_FALSE(r.left_early) << r.output;
  EXPECT_NE(r.output.find("balance: stood"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fall watch: base tilt > "), std::string::npos) << r.output;
}

// the "stood" with thousands of leg IK failures: a stance pose with the legs stretched
// (knees 0: the soles' targets at the edge of the legs' reach, where the stabilizer's height
// corrections put them beyond it) makes the legs' IK fail in most cycles; balance says so and
// exits 9, never "stood"
TEST(FallPrograms, BalanceWithPersistentLegIkFailuresDoesNotSayStood) {
  const std::string pose = ohrp::testing::ScratchFile(
      "straight", "joints:\n  RLEG_KNEE: 0\n  LLEG_KNEE: 0\n", ".yaml");
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.args = {Program("balance"), "--ramp", "1.0", "--pose", pose, "--no-centre-com",
              "--no-self-collision"};
  run.t_end = 6.0;
  const InProcessResult r = RunInProcess("ik_balance", run);
  EXPECT_EQ(r.exit_code, kExitFailed) << r.output;
  EXPECT_EQ(r.output.find("balance: stood"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("balance: FAILED: the legs' inverse kinematics failed persistently"),
            std::string::npos)
      << r.output;
  std::printf("[ figures  ] %s", r.output.substr(r.output.find("balance: did NOT")).c_str());
}

// issue 31: walk starts with the CoM centred and has no --no-centre-com; when the legs cannot
// centre it from the stance pose (knees straight), walk's refusal must not suggest that option
// (balance's still does)
TEST(FallPrograms, WalkRefusalDoesNotSuggestBalancesOption) {
  const std::string pose = ohrp::testing::ScratchFile(
      "straight_walk", "joints:\n  RLEG_KNEE: 0\n  LLEG_KNEE: 0\n", ".yaml");
  for (const char* program : {"walk", "balance"}) {
    InProcessRun run;
    run.io = Hrp1sStanding();
    run.args = {Program(program), "--pose", pose, "--no-self-collision"};
    run.t_end = 3.0;  // refused at once; room for a slow start
    const InProcessResult r = RunInProcess(std::string("centre_") + program, run);
    EXPECT_NE(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("cannot move the CoM over the middle of the soles"), std::string::npos)
        << program << ": " << r.output;
    EXPECT_EQ(r.output.find("--no-centre-com") != std::string::npos,
              std::string(program) == "balance")
        << program << ": " << r.output;
    std::printf("[ figures  ] %s: %s", program, r.output.c_str());
  }
}

// a robot that starts on the floor, on its side (the base turned 90 deg about x, 0.2 m up):
// posture (the IMU's orientation, the default 45 deg) says so within a second
TEST(FallPrograms, ARobotStartingOnItsSideIsAFall) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.setup = [](sim::InProcessRobot* robot) {
    double* q = robot->d()->qpos;  // free joint first: x y z, w x y z
    q[2] = 0.2;
    q[3] = std::cos(M_PI / 4);
    q[4] = std::sin(M_PI / 4);
    q[5] = q[6] = 0;
    mj_forward(robot->m(), robot->d());
  };
  run.args = {Program("posture"), "--ramp", "0.5", "--no-self-collision"};
  run.t_end = 4.0;
  const InProcessResult r = RunInProcess("fall_side", run);
  EXPECT_EQ(r.exit_code, kExitFell) << r.output;
  EXPECT_LT(FallTime(r.output), 1.5) << r.output;
  EXPECT_NE(r.output.find("its base tilted"), std::string::npos) << r.output;
  std::printf("[ figures  ] started on its side: %s", r.output.substr(r.output.find("posture: the robot")).c_str());
}

TEST(FallPrograms, NoFallWatchLetsTheRunGoOn) {
  InProcessRun run;
  run.io = Hrp1sStanding();
  run.args = {Program("posture"), "--ramp", "0.5", "--no-self-collision", "--no-fall-watch"};
  run.t_end = 4.0;
  run.edit_commands = Limp;
  const InProcessResult r = RunInProcess("fall_posture_off", run);
  EXPECT_EQ(r.exit_code, kExitOk) << r.output;
  EXPECT_FALSE(r.left_early) << r.output;
  EXPECT_LT(FallTime(r.output), 0) << r.output;
}

}  // namespace
}  // namespace ohrp::controllers::testing
