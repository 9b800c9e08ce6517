// Tests the playback program across processes: a fake robot (Producer) in the test, the built
// `playback` binary attached to it.
#include "controllers/playback.h"

#include <gtest/gtest.h>
#include <signal.h>

#include <cmath>
#include <cstdio>

#include "controllers/ramp.h"
#include "controllers/runner.h"
#include "controllers/trajectory.h"
#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

using testing::CommandRecord;
using testing::FakeRobot;
using testing::FakeRobotSpec;

constexpr double kRamp = 0.1;     // [s]
constexpr double kRowDt = 0.01;   // [s] between rows of the test trajectory
constexpr int kRows = 51;         // 0 .. 0.5 s
const double kInit[3] = {0.2, -0.1, 0.05};

double Row(int i, int j) { return 0.1 * (j + 1) * std::sin(2 * M_PI * i * kRowDt); }

// the q_ref playback must send at producer time r.time for a start at t0 (written out here,
// independently of the library)
double Expected(double t0, const CommandRecord& r, int j) {
  const double e = r.time - t0;
  if (e < kRamp) return kInit[j] + (Row(0, j) - kInit[j]) * MinimumJerk(e / kRamp);
  const double tt = e - kRamp;
  if (tt >= (kRows - 1) * kRowDt) return Row(kRows - 1, j);
  const int i = static_cast<int>(std::floor(tt / kRowDt));
  const double a = tt / kRowDt - i;
  return Row(i, j) + a * (Row(i + 1, j) - Row(i, j));
}

class PlaybackTest : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = testing::UniqueSegment("playback");
    testing::RemoveSegment(segment_);
    log_ = testing::TempPath("playback_log");
    angles_ = testing::TempPath("angles");
    std::string text;
    char buf[128];
    for (int i = 0; i < kRows; ++i) {
      std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g\n", i * kRowDt, Row(i, 0),
                    Row(i, 1), Row(i, 2));
      text += buf;
    }
    testing::WriteText(angles_, text);
  }
  void TearDown() override {
    testing::RemoveSegment(segment_);
    std::remove(log_.c_str());
    std::remove(angles_.c_str());
  }
  std::string segment_, log_, angles_;
};

TEST_F(PlaybackTest, CommandsFollowTheFileAfterTheRampThenHoldTheLastRow) {
  const std::string gains = testing::TempPath("gains");
  testing::WriteText(gains, "50 5\n\n60 6\n70 7\n");
  FakeRobotSpec spec;
  spec.segment = segment_;
  spec.joints = {"J0", "J1", "J2"};
  spec.q_init.assign(kInit, kInit + 3);
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = testing::Spawn({testing::Program("playback"), "--segment", segment_, "--angles",
                              angles_, "--gains", gains, "--ramp", "0.1", "--attach-timeout",
                              "5"},
                             log_);
  ASSERT_TRUE(robot->RunUntilCommands(170)) << testing::ReadFile(log_);  // 0.85 s

  const auto& rec = robot->records();
  auto error_j1 = [](double t0, const CommandRecord& r, const void*) {
    return r.q_ref[1] - Expected(t0, r, 1);
  };
  const double t0 = testing::FindStartTime(rec, robot->period(), error_j1, nullptr);
  int mid_segment_checks = 0;
  for (const CommandRecord& r : rec) {
    for (int j = 0; j < 3; ++j) {
      EXPECT_NEAR(r.q_ref[j], Expected(t0, r, j), 1e-9) << "joint " << j << " t " << r.time;
      EXPECT_DOUBLE_EQ(r.kp[j], 50.0 + 10 * j);
      EXPECT_DOUBLE_EQ(r.kd[j], 5.0 + j);
    }
    // without a velocity file, dq_ref is the slope between neighbouring rows
    const double tt = r.time - t0 - kRamp;
    const double rows = tt / kRowDt;
    const int i = static_cast<int>(std::floor(rows));
    if (tt > 0 && i < kRows - 1 && std::abs(rows - i - 0.5) < 0.25) {
      ++mid_segment_checks;
      for (int j = 0; j < 3; ++j) {
        EXPECT_NEAR(r.dq_ref[j], (Row(i + 1, j) - Row(i, j)) / kRowDt, 1e-6);
      }
    }
  }
  EXPECT_GT(mid_segment_checks, 40);
  ASSERT_GT(rec.back().time - t0, kRamp + 0.5);  // the hold was reached
  for (int j = 0; j < 3; ++j) {
    EXPECT_NEAR(rec.back().q_ref[j], Row(kRows - 1, j), 1e-12);
    EXPECT_EQ(rec.back().dq_ref[j], 0.0);
  }
  robot->Stop();
  EXPECT_EQ(testing::WaitExit(pid, 10.0), kExitOk) << testing::ReadFile(log_);
  std::remove(gains.c_str());
}

TEST_F(PlaybackTest, RefusesARobotWithAnotherJointCount) {
  FakeRobotSpec spec;
  spec.segment = segment_;
  spec.robot_name = "Five";
  spec.joints = {"A", "B", "C", "D", "E"};
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = testing::Spawn(
      {testing::Program("playback"), "--segment", segment_, "--angles", angles_}, log_);
  EXPECT_EQ(robot->RunUntilExit(pid), kExitConfig);
  const std::string log = testing::ReadFile(log_);
  EXPECT_NE(log.find("has 3 joint columns after the time, but the robot has 5 joints"),
            std::string::npos)
      << log;
  EXPECT_TRUE(robot->records().empty());
}

TEST_F(PlaybackTest, PlaysSamplePDWithItsVelocitiesAndGainsAndStopsOnSigterm) {
  const std::string ext = testing::ExternalDir();
  if (ext.empty()) GTEST_SKIP() << "reference data not found (set OHRP_EXTERNAL_DIR)";
  const std::string dir = ext + "/openhrp3-sample/SamplePD";
  Trajectory angles, velocities;
  ASSERT_TRUE(LoadTrajectory(dir + "/angle.dat", &angles).ok());
  ASSERT_TRUE(LoadTrajectory(dir + "/vel.dat", &velocities).ok());
  FakeRobotSpec spec;
  spec.segment = segment_;
  spec.joints = testing::SampleRobotJoints();
  std::string error;
  auto robot = FakeRobot::Create(spec, &error);
  ASSERT_TRUE(robot) << error;
  pid_t pid = testing::Spawn(
      {testing::Program("playback"), "--segment", segment_, "--angles", dir + "/angle.dat",
       "--velocities", dir + "/vel.dat", "--gains", dir + "/PDgain.dat", "--ramp", "0.05",
       "--time-scale", "2", "--attach-timeout", "5"},
      log_);
  ASSERT_TRUE(robot->RunUntilCommands(150)) << testing::ReadFile(log_);

  struct Ctx { const Trajectory* angles; };
  Ctx ctx{&angles};
  auto knee_error = [](double t0, const CommandRecord& r, const void* c) {
    const Trajectory& a = *static_cast<const Ctx*>(c)->angles;
    const double e = r.time - t0;
    if (e < 0.05) return 0.0;  // the ramp: not modelled here
    double q[29];
    SampleTrajectory(a, (e - 0.05) * 2.0, q);
    return r.q_ref[3] - q[3];
  };
  const double t0 = testing::FindStartTime(robot->records(), robot->period(), knee_error, &ctx);
  int checked = 0;
  for (const CommandRecord& r : robot->records()) {
    EXPECT_DOUBLE_EQ(r.kp[0], 8000.0);
    EXPECT_DOUBLE_EQ(r.kd[0], 100.0);
    EXPECT_DOUBLE_EQ(r.kp[6], 3000.0);
    const double e = r.time - t0;
    if (e < 0.06) continue;
    double q[29], dq[29];
    SampleTrajectory(angles, (e - 0.05) * 2.0, q);
    SampleTrajectory(velocities, (e - 0.05) * 2.0, dq);
    for (int j = 0; j < 29; ++j) {
      EXPECT_NEAR(r.q_ref[j], q[j], 1e-9) << j;
      EXPECT_NEAR(r.dq_ref[j], 2.0 * dq[j], 1e-9) << j;  // vel.dat times --time-scale
    }
    ++checked;
  }
  EXPECT_GT(checked, 100);

  // SIGTERM: a clean stop that frees the controller slot
  kill(pid, SIGTERM);
  EXPECT_EQ(robot->RunUntilExit(pid), kExitOk) << testing::ReadFile(log_);
  EXPECT_EQ(robot->controller_pid(), 0);
  EXPECT_NE(testing::ReadFile(log_).find("stopped by signal"), std::string::npos);
}

}  // namespace
}  // namespace ohrp::controllers
