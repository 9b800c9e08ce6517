// Tests the walk checks goal_reached and average_speed (tools/runner/src/walk_checks.cc) on
// synthetic logs of a base moving along known paths: the relative pose, the unwrapped heading
// and the moving time are known in closed form.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "runner/checks.h"
#include "runner/walk_checks.h"
#include "temp_file.h"

namespace ohrp::runner {
namespace {

constexpr double kDt = 0.01;      // [s] log period of the synthetic logs
constexpr double kDeg = M_PI / 180;

// the base at one time: horizontal position [m] and heading [rad] (upright)
struct Pose {
  double x = 0, y = 0, yaw = 0;
};

// a log of the base following `at` over [0, duration]
datalog::Table Log(double duration, const std::function<Pose(double)>& at) {
  std::string csv = "time,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz\n";
  char row[256];
  for (int i = 0; i <= std::lround(duration / kDt); ++i) {
    const double t = i * kDt;
    const Pose p = at(t);
    std::snprintf(row, sizeof(row), "%.17g,%.17g,%.17g,0.7,%.17g,0,0,%.17g\n", t, p.x, p.y,
                  std::cos(p.yaw / 2), std::sin(p.yaw / 2));
    csv += row;
  }
  datalog::Table t;
  std::string error;
  EXPECT_TRUE(t.Load(Temp(csv, ".csv"), &error)) << error;
  return t;
}

CheckSpec Spec(const std::string& type, std::map<std::string, std::string> p) {
  CheckSpec s;
  s.type = type;
  s.params = std::move(p);
  return s;
}

// standing 2 s at (1, 2) facing 30 deg, then 10 m along that heading at 0.3 m/s, then
// standing 2 s
constexpr double kSpeed = 0.3;  // [m/s]
constexpr double kWalkStart = 2.0, kWalkTime = 10 / kSpeed;  // [s]
datalog::Table StraightWalk() {
  const double h = 30 * kDeg;
  return Log(kWalkStart + kWalkTime + 2, [=](double t) {
    const double s = kSpeed * std::clamp(t - kWalkStart, 0.0, kWalkTime);
    return Pose{1 + s * std::cos(h), 2 + s * std::sin(h), h};
  });
}

TEST(GoalReached, MeasuresTheGoalInTheInitialHeadingFrame) {
  RelativePose p;
  std::string error;
  ASSERT_TRUE(FinalRelativePose(StraightWalk(), &p, &error)) << error;
  EXPECT_NEAR(p.x, 10, 1e-9);  // all of it forward, though the world sees it at 30 deg
  EXPECT_NEAR(p.y, 0, 1e-9);
  EXPECT_NEAR(p.yaw, 0, 1e-9);
  const auto r = Evaluate(Spec("goal_reached", {{"x", "10"}}), StraightWalk(), {});
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0, 1e-9);
}

TEST(GoalReached, FailsOffTheGoalOrItsHeading) {
  // 0.25 m beside the goal (tolerance 0.2 m by default); 0.15 m passes
  auto r = Evaluate(Spec("goal_reached", {{"x", "10"}, {"y", "0.25"}}), StraightWalk(), {});
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.value, 0.25, 1e-9);
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"x", "10"}, {"y", "0.15"}}), StraightWalk(), {}).passed);
  // 6 deg off the heading (tolerance 5 deg by default), the position right
  r = Evaluate(Spec("goal_reached", {{"x", "10"}, {"yaw_deg", "6"}}), StraightWalk(), {});
  EXPECT_FALSE(r.passed);
  EXPECT_NEAR(r.value, 0, 1e-9);
  EXPECT_NE(r.detail.find("6 deg off"), std::string::npos) << r.detail;
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"x", "10"}, {"yaw_deg", "6"}, {"tolerance_deg", "7"}}),
                       StraightWalk(), {}).passed);
}

// facing +y, 1 m to its left is 1 m along the world's -x
TEST(GoalReached, ASideStepIsAlongTheInitialY) {
  const datalog::Table log = Log(4, [](double t) { return Pose{-std::min(t, 2.0) / 2, 0, 90 * kDeg}; });
  RelativePose p;
  std::string error;
  ASSERT_TRUE(FinalRelativePose(log, &p, &error)) << error;
  EXPECT_NEAR(p.x, 0, 1e-9);
  EXPECT_NEAR(p.y, 1, 1e-9);
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"y", "1"}}), log, {}).passed);
  EXPECT_FALSE(Evaluate(Spec("goal_reached", {{"y", "-1"}}), log, {}).passed);
}

// a settling shift before the walk (0.07 m forward while turned 90 deg), then a closed path
// back to where the walk began: judged from `from`, the path closes; from the start, it does not
TEST(GoalReached, FromJudgesThePoseFromThatTimeInItsHeading) {
  const datalog::Table log = Log(10, [](double t) {
    const double shift = 0.07 * std::min(t, 1.0);
    const double h = t < 2 ? 90 * kDeg : t < 8 ? 90 * kDeg + (t - 2) / 6 * 2 * M_PI : 450 * kDeg;
    return Pose{0, shift, h};
  });
  RelativePose p;
  std::string error;
  ASSERT_TRUE(FinalRelativePose(log, &p, &error, 1.5)) << error;
  EXPECT_NEAR(p.x, 0, 1e-9);
  EXPECT_NEAR(p.y, 0, 1e-9);
  EXPECT_NEAR(p.yaw, 2 * M_PI, 1e-9);
  auto r = Evaluate(Spec("goal_reached", {{"yaw_deg", "360"}, {"tolerance", "0.01"}, {"from", "1.5"}}), log, {});
  EXPECT_TRUE(r.passed) << r.detail;
  r = Evaluate(Spec("goal_reached", {{"yaw_deg", "360"}, {"tolerance", "0.01"}}), log, {});
  EXPECT_FALSE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 0.07, 1e-9);
  EXPECT_FALSE(FinalRelativePose(log, &p, &error, 11.0));
  EXPECT_NE(error.find("ends before"), std::string::npos) << error;
}

// a turn on the spot from 170 deg, through the +-180 deg seam of the quaternion's heading
TEST(GoalReached, ATurnIsUnwrappedOverTheRun) {
  const auto turn = [](double by_deg) {
    return Log(6, [=](double t) { return Pose{0, 0, (170 + by_deg * std::min(t, 5.0) / 5) * kDeg}; });
  };
  const datalog::Table half = turn(180), full = turn(360), back = turn(-180);
  EXPECT_NEAR(UnwrappedYaw(half).back() - UnwrappedYaw(half).front(), M_PI, 1e-9);
  EXPECT_NEAR(UnwrappedYaw(full).back() - UnwrappedYaw(full).front(), 2 * M_PI, 1e-9);
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"yaw_deg", "180"}}), half, {}).passed);
  EXPECT_FALSE(Evaluate(Spec("goal_reached", {{"yaw_deg", "-180"}}), half, {}).passed);
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"yaw_deg", "-180"}}), back, {}).passed);
  EXPECT_TRUE(Evaluate(Spec("goal_reached", {{"yaw_deg", "360"}}), full, {}).passed);
  const auto r = Evaluate(Spec("goal_reached", {}), full, {});  // back where it started, but turned
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("yaw 360 deg"), std::string::npos) << r.detail;
}

TEST(GoalReached, YawOfAQuaternionIsItsHeading) {
  EXPECT_NEAR(YawOf(std::cos(0.3), 0, 0, std::sin(0.3)), 0.6, 1e-12);
  EXPECT_NEAR(YawOf(2 * std::cos(0.3), 0, 0, 2 * std::sin(0.3)), 0.6, 1e-12);  // not unit
  // yaw 40 deg, then pitch 10 deg about the turned y: the heading stays 40 deg
  const double cy = std::cos(20 * kDeg), sy = std::sin(20 * kDeg);
  const double cp = std::cos(5 * kDeg), sp = std::sin(5 * kDeg);
  EXPECT_NEAR(YawOf(cy * cp, -sy * sp, cy * sp, sy * cp), 40 * kDeg, 1e-12);
}

// 10 m in 33.3 s; it is 2 cm from its start at 2 + 0.02 / 0.3 = 2.067 s and 2 cm from its end
// at 2 + (10 - 0.02) / 0.3 = 35.267 s: the first rows after are 2.07 and 35.27 s, 10 m over 33.2 s
TEST(AverageSpeed, IsTheDistanceOverTheTimeItMoved) {
  Motion m;
  std::string error;
  ASSERT_TRUE(MeasureMotion(StraightWalk(), 0.02, &m, &error)) << error;
  EXPECT_TRUE(m.started);
  EXPECT_NEAR(m.distance, 10, 1e-9);
  EXPECT_NEAR(m.start, kWalkStart + 0.02 / kSpeed, kDt + 1e-9);
  EXPECT_NEAR(m.end, kWalkStart + (10 - 0.02) / kSpeed, kDt + 1e-9);
  const auto r = Evaluate(Spec("average_speed", {{"min", "0.3"}}), StraightWalk(), {});
  EXPECT_TRUE(r.passed) << r.detail;
  EXPECT_NEAR(r.value, 10 / 33.2, 1e-9);
  EXPECT_NE(r.detail.find("t=2.07 s"), std::string::npos) << r.detail;
  EXPECT_NE(r.detail.find("t=35.27 s"), std::string::npos) << r.detail;
  EXPECT_FALSE(Evaluate(Spec("average_speed", {{"min", "0.31"}}), StraightWalk(), {}).passed);
}

// walking past the goal and back: timed until it first comes within 2 cm of where it ends
TEST(AverageSpeed, EndsWhenTheBaseFirstReachesItsFinalPosition) {
  const datalog::Table log = Log(8, [](double t) {
    return Pose{t < 4 ? 0.5 * t : std::max(2.0 - 0.5 * (t - 4), 1.5), 0, 0};
  });
  Motion m;
  std::string error;
  ASSERT_TRUE(MeasureMotion(log, 0.02, &m, &error)) << error;
  EXPECT_NEAR(m.distance, 1.5, 1e-9);
  EXPECT_NEAR(m.start, 0.04, kDt + 1e-9);
  EXPECT_NEAR(m.end, (1.5 - 0.02) / 0.5, kDt + 1e-9);
}

TEST(AverageSpeed, FailsWhenTheBaseDoesNotMove) {
  const datalog::Table still = Log(3, [](double) { return Pose{0.3, 0.1, 0}; });
  auto r = Evaluate(Spec("average_speed", {{"min", "0.1"}}), still, {});
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("never went 20 mm from its start"), std::string::npos) << r.detail;
  // 3 cm in all: 2 cm from its start it is already within 2 cm of its end, no time to count
  const datalog::Table creep = Log(3, [](double t) { return Pose{0.03 * std::min(t, 1.0), 0, 0}; });
  r = Evaluate(Spec("average_speed", {{"min", "0.1"}}), creep, {});
  EXPECT_FALSE(r.passed);
  EXPECT_NE(r.detail.find("too little motion"), std::string::npos) << r.detail;
}

}  // namespace
}  // namespace ohrp::runner
