// Tests the replay plugin's reading of sim_host's CSV data log: columns found by name,
// interpolation and steps, finite-difference velocities, and the errors for a log that does
// not fit the robot.
#include "common/scratch.h"
#include "csv_log.h"

#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace ohrp::hw::replay {
namespace {

class CsvLogTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = ohrp::testing::ScratchPath("csv_log", ".csv");
    config_.joint_names = {"a", "b"};
    config_.force_names = {"ft"};
    config_.imu_names = {"imu"};
    config_.period = 0.001;
  }
  void TearDown() override { std::filesystem::remove(path_); }
  void Write(const std::string& text) { std::ofstream(path_) << text; }

  std::filesystem::path path_;
  IoConfig config_;
};

// time, q_a, q_b, tau_a, ft_fz (other columns absent: zero, identity quaternion)
constexpr const char* kLog =
    "time,q_b,q_a,tau_a,ft_fz,status\n"
    "0.0,0.0,1.0,5,10,1\n"
    "0.1,-0.2,2.0,6,20,1\n"
    "0.2,-0.4,4.0,7,30,1\n";

TEST_F(CsvLogTest, FindsColumnsByNameAndInterpolatesInTime) {
  Write(kLog);
  CsvLog log;
  std::string error;
  ASSERT_TRUE(log.Load(path_.string(), config_, &error)) << error;
  EXPECT_EQ(log.rows(), 3);
  EXPECT_DOUBLE_EQ(log.last_time(), 0.2);
  IoState s;
  int cursor = 0;
  log.Sample(0.05, false, &cursor, &s);
  EXPECT_NEAR(s.q[0], 1.5, 1e-12);
  EXPECT_NEAR(s.q[1], -0.1, 1e-12);
  EXPECT_NEAR(s.tau[0], 5.5, 1e-12);
  EXPECT_DOUBLE_EQ(s.tau[1], 0.0);
  EXPECT_NEAR(s.force[0].force[2], 15, 1e-12);
  EXPECT_DOUBLE_EQ(s.imu[0].quat_WI[0], 1.0);
  // velocities: one-sided at row 0 (10 rad/s), central at row 1 (15 rad/s)
  EXPECT_NEAR(s.dq[0], 12.5, 1e-9);
  EXPECT_NEAR(s.dq[1], -2.0, 1e-9);
  log.Sample(0.15, true, &cursor, &s);  // step: the row at or before t
  EXPECT_DOUBLE_EQ(s.q[0], 2.0);
  log.Sample(5.0, false, &cursor, &s);  // past the end: the last row
  EXPECT_DOUBLE_EQ(s.q[0], 4.0);
  log.Sample(0.0, false, &cursor, &s);  // back to the start (a loop)
  EXPECT_DOUBLE_EQ(s.q[0], 1.0);
}

TEST_F(CsvLogTest, ALogOfAnotherRobotNamesTheMissingColumn) {
  Write("time,q_a,q_c\n0,1,2\n");
  CsvLog log;
  std::string error;
  EXPECT_FALSE(log.Load(path_.string(), config_, &error));
  EXPECT_NE(error.find("q_b"), std::string::npos) << error;
}

TEST_F(CsvLogTest, TimeThatDoesNotIncreaseIsAnErrorWithItsLine) {
  Write("time,q_a,q_b\n0,1,2\n0.1,1,2\n0.1,1,2\n");
  CsvLog log;
  std::string error;
  EXPECT_FALSE(log.Load(path_.string(), config_, &error));
  EXPECT_NE(error.find(":4:"), std::string::npos) << error;
}

TEST_F(CsvLogTest, MissingFileAndMalformedRowsAreErrors) {
  CsvLog log;
  std::string error;
  EXPECT_FALSE(log.Load("/nonexistent/log.csv", config_, &error));
  EXPECT_NE(error.find("/nonexistent/log.csv"), std::string::npos) << error;
  Write("time,q_a,q_b\n0,1\n");
  EXPECT_FALSE(log.Load(path_.string(), config_, &error));
  EXPECT_NE(error.find("fields"), std::string::npos) << error;
  Write("time,q_a,q_b\n0,x,1\n");
  CsvLog log2;
  EXPECT_FALSE(log2.Load(path_.string(), config_, &error));
  EXPECT_NE(error.find("not a number"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::hw
