// Tests the OpenHRP trajectory and gain loaders (controllers/trajectory.h) and interpolation.
#include "controllers/trajectory.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "fake_robot.h"

namespace ohrp::controllers {
namespace {

// SamplePD's walking data, or "" when the reference data is not on this machine
std::string SamplePD() {
  const std::string dir = testing::ExternalDir();
  return dir.empty() ? dir : dir + "/openhrp3-sample/SamplePD";
}

ConfigStatus Parse(const std::string& text, Trajectory* out) {
  std::istringstream in(text);
  return ParseTrajectory(in, "t.dat", out);
}

TEST(TrajectoryTest, ParsesAGoodFile) {
  Trajectory tr;
  ConfigStatus s = Parse("# comment\n0 1.0 2.0\n\n0.5\t3.0  4.0\r\n1.0 +5e0 -6.0E+00\n", &tr);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(tr.njoint, 2);
  ASSERT_EQ(tr.rows(), 3u);
  EXPECT_DOUBLE_EQ(tr.time[1], 0.5);
  EXPECT_DOUBLE_EQ(tr.row(2)[0], 5.0);
  EXPECT_DOUBLE_EQ(tr.row(2)[1], -6.0);
  EXPECT_EQ(tr.line[1], 4);
}

TEST(TrajectoryTest, MalformedRowNamesFileAndLine) {
  Trajectory tr;
  ConfigStatus s = Parse("0 1 2\n0.1 1 2\n0.2 1 x2\n", &tr);
  EXPECT_EQ(s.code, ConfigError::kSyntax);
  EXPECT_NE(s.message.find("t.dat:3:"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("'x2'"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("joint 1"), std::string::npos) << s.message;
}

TEST(TrajectoryTest, WrongColumnCountIsRefused) {
  Trajectory tr;
  ConfigStatus s = Parse("0 1 2 3\n0.1 1 2\n", &tr);
  EXPECT_EQ(s.code, ConfigError::kColumns);
  EXPECT_NE(s.message.find("t.dat:2:"), std::string::npos) << s.message;
  EXPECT_NE(s.message.find("expected 3"), std::string::npos) << s.message;
  EXPECT_EQ(Parse("0\n", &tr).code, ConfigError::kColumns);
}

TEST(TrajectoryTest, NanAndInfinityAreRefused) {
  Trajectory tr;
  ConfigStatus s = Parse("0 1 2\n0.1 nan 2\n", &tr);
  EXPECT_EQ(s.code, ConfigError::kNonFinite);
  EXPECT_NE(s.message.find("t.dat:2:"), std::string::npos) << s.message;
  EXPECT_EQ(Parse("0 1 inf\n", &tr).code, ConfigError::kNonFinite);
  EXPECT_EQ(Parse("NaN 1 2\n", &tr).code, ConfigError::kNonFinite);
}

TEST(TrajectoryTest, NonMonotonicTimeIsRefused) {
  Trajectory tr;
  ConfigStatus s = Parse("0 1\n0.2 1\n0.1 1\n", &tr);
  EXPECT_EQ(s.code, ConfigError::kTime);
  EXPECT_NE(s.message.find("t.dat:3:"), std::string::npos) << s.message;
  EXPECT_EQ(Parse("0 1\n0 2\n", &tr).code, ConfigError::kTime);  // repeated time
}

TEST(TrajectoryTest, EmptyAndMissingFilesAreRefused) {
  Trajectory tr;
  EXPECT_EQ(Parse("# nothing\n\n", &tr).code, ConfigError::kEmpty);
  ConfigStatus s = LoadTrajectory("/nonexistent/angle.dat", &tr);
  EXPECT_EQ(s.code, ConfigError::kFile);
  EXPECT_NE(s.message.find("/nonexistent/angle.dat"), std::string::npos);
}

TEST(TrajectoryTest, LoadsSamplePDWalk) {
  const std::string kSamplePD = SamplePD();
  if (kSamplePD.empty()) GTEST_SKIP() << "reference data not found (set OHRP_EXTERNAL_DIR)";
  Trajectory angles, velocities;
  ConfigStatus s = LoadTrajectory(kSamplePD + "/angle.dat", &angles);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_EQ(angles.njoint, 29);
  EXPECT_EQ(angles.rows(), 6701u);
  EXPECT_NEAR(angles.end_time(), 13.4, 1e-9);
  EXPECT_DOUBLE_EQ(angles.row(0)[3], 0.0785);   // RLEG_KNEE at t = 0
  EXPECT_DOUBLE_EQ(angles.row(0)[9], -1.57);    // RARM_ELBOW
  s = LoadTrajectory(kSamplePD + "/vel.dat", &velocities);
  ASSERT_TRUE(s.ok()) << s.message;
  EXPECT_TRUE(CheckCompanion(angles, velocities).ok());
}

TEST(TrajectoryTest, CompanionWithOtherTimesIsRefused) {
  Trajectory a, v;
  ASSERT_TRUE(Parse("0 1\n0.1 2\n", &a).ok());
  ASSERT_TRUE(Parse("0 1\n0.2 2\n", &v).ok());
  EXPECT_EQ(CheckCompanion(a, v).code, ConfigError::kMismatch);
  ASSERT_TRUE(Parse("0 1 1\n0.1 2 2\n", &v).ok());
  EXPECT_EQ(CheckCompanion(a, v).code, ConfigError::kMismatch);
}

TEST(TrajectoryTest, InterpolatesLinearlyAndHoldsTheEnds) {
  Trajectory tr;
  ASSERT_TRUE(Parse("1.0 0 10\n2.0 1 20\n4.0 -1 20\n", &tr).ok());
  double q[2], dq[2];
  SampleTrajectory(tr, 1.5, q);
  EXPECT_DOUBLE_EQ(q[0], 0.5);
  EXPECT_DOUBLE_EQ(q[1], 15.0);
  SampleTrajectory(tr, 3.0, q);
  EXPECT_DOUBLE_EQ(q[0], 0.0);
  SampleTrajectory(tr, 2.0, q);  // exactly on a row
  EXPECT_DOUBLE_EQ(q[0], 1.0);
  SampleTrajectory(tr, 0.0, q);  // before the start: the first row
  EXPECT_DOUBLE_EQ(q[0], 0.0);
  EXPECT_DOUBLE_EQ(q[1], 10.0);
  SampleTrajectory(tr, 100.0, q);  // after the end: hold the last row
  EXPECT_DOUBLE_EQ(q[0], -1.0);
  SampleSlope(tr, 1.5, dq);
  EXPECT_DOUBLE_EQ(dq[0], 1.0);
  EXPECT_DOUBLE_EQ(dq[1], 10.0);
  SampleSlope(tr, 3.0, dq);
  EXPECT_DOUBLE_EQ(dq[0], -1.0);
  SampleSlope(tr, 5.0, dq);
  EXPECT_DOUBLE_EQ(dq[0], 0.0);
}

// found by fuzz/trajectory_fuzz.cc: finite rows far apart (their difference overflows) still
// interpolate to finite values between them, and the last row is reached exactly
TEST(TrajectoryTest, InterpolatesBetweenHugeValuesWithoutOverflow) {
  Trajectory tr;
  ASSERT_TRUE(Parse("0 -1.5e308 1.5e308\n1 1.5e308 -1.5e308\n", &tr).ok());
  double q[2];
  SampleTrajectory(tr, 0.5, q);
  EXPECT_TRUE(std::isfinite(q[0]) && std::isfinite(q[1])) << q[0] << " " << q[1];
  EXPECT_NEAR(q[0], 0.0, 1e293);
  ASSERT_TRUE(Parse("-0.4 3\n1 0.3\n", &tr).ok());
  SampleTrajectory(tr, std::nextafter(1.0, 0.0), q);  // just before the last row
  EXPECT_GE(q[0], 0.3);
}

TEST(GainsTest, LoadsSamplePDGainsSkippingBlankLines) {
  const std::string kSamplePD = SamplePD();
  if (kSamplePD.empty()) GTEST_SKIP() << "reference data not found (set OHRP_EXTERNAL_DIR)";
  Gains g;
  ConfigStatus s = LoadGains(kSamplePD + "/PDgain.dat", &g);
  ASSERT_TRUE(s.ok()) << s.message;
  ASSERT_EQ(g.kp.size(), 29u);
  EXPECT_DOUBLE_EQ(g.kp[0], 8000.0);
  EXPECT_DOUBLE_EQ(g.kd[0], 100.0);
  EXPECT_DOUBLE_EQ(g.kp[6], 3000.0);
}

TEST(GainsTest, MalformedGainRowIsRefused) {
  Gains g;
  std::istringstream three("1 2\n1 2 3\n");
  ConfigStatus s = ParseGains(three, "g.dat", &g);
  EXPECT_EQ(s.code, ConfigError::kColumns);
  EXPECT_NE(s.message.find("g.dat:2:"), std::string::npos) << s.message;
  std::istringstream negative("1 -2\n");
  EXPECT_EQ(ParseGains(negative, "g.dat", &g).code, ConfigError::kSyntax);
  std::istringstream nan("nan 2\n");
  EXPECT_EQ(ParseGains(nan, "g.dat", &g).code, ConfigError::kNonFinite);
}

}  // namespace
}  // namespace ohrp::controllers
