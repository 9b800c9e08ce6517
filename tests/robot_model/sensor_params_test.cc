// The sensor file (robot_model/sensor_params.h): read, written and read back with every key,
// bound to a robot, and refused with the file, line and key when a value is wrong.
#include "robot_model/sensor_params.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/scratch.h"

namespace ohrp::model {
namespace {

std::string Write(const std::string& text) { return ohrp::testing::ScratchFile("sensors", text, ".yaml"); }

TEST(SensorParamsFile, EveryKeyReadWrittenAndReadBack) {
  const std::string path = Write(
      "encoders:\n"
      "  KNEE: {bias: 0.01, noise: 2.0e-4, velocity_noise: 1.0e-3, torque_noise: 0.2}\n"
      "imus:\n"
      "  gyro: {gyro_bias: [0.01, 0, 0], gyro_noise: [0.003, 0.003, 0.003], accel_noise: [0.03, 0.03, 0.03],\n"
      "         orientation_noise: 2.0e-3}\n"
      "force_torque:\n"
      "  rf: {bias: [0, 0, 1.5, 0, 0, 0], noise: [2, 2, 2, 0.1, 0.1, 0.1]}\n");
  SensorParams p;
  std::string error;
  ASSERT_TRUE(ReadSensorParamsFile(path, &p, &error)) << error;
  ASSERT_EQ(p.encoders.size(), 1u);
  EXPECT_EQ(p.encoders[0].velocity_noise, 1.0e-3);
  EXPECT_EQ(p.encoders[0].torque_noise, 0.2);
  EXPECT_EQ(p.imus[0].orientation_noise, 2.0e-3);
  const std::string again = ohrp::testing::ScratchPath("sensors_again", ".yaml");
  ASSERT_TRUE(WriteSensorParamsFile(again, p, {"written by the test"}, &error)) << error;
  SensorParams q;
  ASSERT_TRUE(ReadSensorParamsFile(again, &q, &error)) << error;
  EXPECT_EQ(q.encoders[0].bias, 0.01);
  EXPECT_EQ(q.encoders[0].velocity_noise, 1.0e-3);
  EXPECT_EQ(q.encoders[0].torque_noise, 0.2);
  EXPECT_EQ(q.imus[0].orientation_noise, 2.0e-3);
  EXPECT_EQ(q.forces[0].bias[2], 1.5);
  EXPECT_NE(DescribeSensorParams(q).find("IMU gyro bias noise"), std::string::npos) << DescribeSensorParams(q);
}

TEST(SensorParamsFile, AWrongValueNamesFileLineAndKey) {
  SensorParams p;
  std::string error;
  const std::string path = Write("encoders:\n  KNEE: {noise: 1.0e-4}\nimus:\n  gyro: {orientation_noise: -1}\n");
  EXPECT_FALSE(ReadSensorParamsFile(path, &p, &error));
  EXPECT_EQ(error, path + ":4: imus: gyro: orientation_noise: '-1' is not a number in [0, 0.1]");
  const std::string big = Write("encoders:\n  KNEE: {torque_noise: 80}\n");
  EXPECT_FALSE(ReadSensorParamsFile(big, &p, &error));
  EXPECT_NE(error.find(big + ":2: encoders: KNEE: torque_noise: '80' is not a number in [0, 50]"), std::string::npos) << error;
}

// the orientation's error: a rotation whose vector has the given std per axis (2 q_x for small
// angles), the quaternion kept unit
TEST(SensorModelNoise, OrientationErrorHasItsStandardDeviation) {
  SensorParams p;
  p.imus.resize(1);
  p.imus[0].orientation_noise = 0.01;
  SensorModel m(p, 7);
  const int n = 40000;
  double s = 0, worst = 0;
  for (int i = 0; i < n; ++i) {
    double q[4] = {1, 0, 0, 0};
    m.Orientation(0, q);
    s += 4 * q[1] * q[1];
    worst = std::fmax(worst, std::fabs(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] - 1));
  }
  EXPECT_NEAR(std::sqrt(s / n), 0.01, 0.02 * 0.01);  // 1/sqrt(2N) = 0.35 % relative spread
  EXPECT_LT(worst, 1e-12);
  double q[4] = {1, 0, 0, 0};
  m.Orientation(1, q);  // no such IMU: as simulated
  EXPECT_EQ(q[0], 1.0);
}

}  // namespace
}  // namespace ohrp::model
