// ohrp identify --sensors: the noise of the channels the robot's own motion moves too (a joint's
// velocity and torque, the IMU's orientation), against closed forms. Each synthetic signal is a
// fast motion (12 Hz: the 51-sample moving average at 1 ms leaves about half of it) that the
// regressors measure, plus white noise of known std; each estimate within 4 of its standard
// errors, the standard error against sigma / sqrt(2 N); the moving average alone is shown biased
// by the motion (why it is fitted away); a turning IMU refused and a motion that explains most of
// a channel warned about.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "common/scratch.h"
#include "identify/sensors.h"

namespace ohrp::identify {
namespace {

constexpr double kDt = 1e-3, kF = 12.0;
constexpr int kRows = 6000;

TEST(MotionNoise, ATorqueFollowingTheServoIsFittedAwayAndTheNoiseRemains) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  const double sigma = 0.05, w = 2 * M_PI * kF;
  std::vector<double> tau, q, dq;
  for (int k = 0; k < kRows; ++k) {
    const double t = k * kDt, y = 0.01 * std::sin(w * t) + 0.004 * std::sin(2.7 * w * t + 1);
    const double v = 0.01 * w * std::cos(w * t) + 0.004 * 2.7 * w * std::cos(2.7 * w * t + 1);
    q.push_back(y + 1e-5 * n(rng)), dq.push_back(v + 1e-4 * n(rng));
    tau.push_back(3.0 - 100 * y - 0.5 * v + sigma * n(rng));
  }
  double explained = 0;
  const Stat s = NoiseBeyondMotion(tau, {q, dq}, 51, &explained);
  EXPECT_NEAR(s.value, sigma, 4 * s.se);
  // the standard error: sigma / sqrt(2 dof), dof = the high-passed rows less the fit's 3
  EXPECT_NEAR(s.se, sigma / std::sqrt(2.0 * (kRows - 50 - 3)), 0.05 * s.se);
  EXPECT_GT(explained, 0.9);
  // the moving average alone leaves the 12 Hz motion in: far above the noise
  EXPECT_GT(NoiseStd(tau, 51).value, 5 * sigma);
  // no regressors: the white noise's std as NoiseStd gives it
  const Stat plain = NoiseBeyondMotion(std::vector<double>(tau.begin(), tau.end()), {}, 51);
  EXPECT_NEAR(plain.value, NoiseStd(tau, 51).value, 1e-3 * plain.value);
}

// a still log at 1 ms of one joint vibrating at 12 Hz (amplitude `amp` rad: velocity and torque
// follow), an IMU swaying at 12 Hz about x and z (5e-5 rad) whose orientation is turned by noise
// of `orient` rad per axis, the gyro measuring the sway; `drift` [rad/s] a slow turn about x
std::string WriteLog(double amp, double drift, double vel_noise, double tau_noise, double orient) {
  const std::string path = ohrp::testing::ScratchPath("motion", ".csv");
  std::ofstream f(path);
  f.precision(12);
  f << "time,q_J,qref_J,tau_J,dq_J,I_gx,I_gy,I_gz,I_ax,I_ay,I_az,I_qw,I_qx,I_qy,I_qz,status\n";
  std::mt19937 rng(17);
  std::normal_distribution<double> n(0.0, 1.0);
  const double w = 2 * M_PI * kF;
  for (int k = 0; k < kRows; ++k) {
    const double t = k * kDt, y = amp * std::sin(w * t), v = amp * w * std::cos(w * t);
    const double ax = 5e-5 * std::sin(w * t) + drift * t, az = 5e-5 * std::sin(w * t + 0.7);
    const double rx = 5e-5 * w * std::cos(w * t) + drift, rz = 5e-5 * w * std::cos(w * t + 0.7);
    // the true orientation: about x then z (small angles: the gyro reads their rates), then the
    // sensor's error on the right, a rotation vector of `orient` per axis
    const Eigen::Vector3d e(orient * n(rng), orient * n(rng), orient * n(rng));
    Eigen::Quaterniond qt = Eigen::Quaterniond(Eigen::AngleAxisd(ax, Eigen::Vector3d::UnitX())) *
                            Eigen::Quaterniond(Eigen::AngleAxisd(az, Eigen::Vector3d::UnitZ()));
    if (e.norm() > 0) qt = qt * Eigen::Quaterniond(Eigen::AngleAxisd(e.norm(), e.normalized()));
    f << t << "," << 0.3 + y + 1e-7 * n(rng) << ",0.3," << 2.0 - 500 * y - 2 * v + tau_noise * n(rng)
      << "," << v + vel_noise * n(rng) << "," << rx + 1e-3 * n(rng) << "," << 1e-3 * n(rng) << ","
      << rz + 1e-3 * n(rng) << ",0,0,9.81," << qt.w() << "," << qt.x() << "," << qt.y() << ","
      << qt.z() << ",0\n";
  }
  return path;
}

TEST(MotionNoise, AStillLogsVelocityTorqueAndOrientationNoise) {
  SensorEstimates s;
  std::string error;
  const double vel = 2e-3, tau = 0.3, orient = 5e-5;
  ASSERT_TRUE(EstimateSensors(WriteLog(2e-4, 0, vel, tau, orient), SensorOptions{}, &s, &error)) << error;
  ASSERT_EQ(s.velocity_noise.size(), 1u);
  EXPECT_NEAR(s.velocity_noise[0].value, vel, 4 * s.velocity_noise[0].se);
  EXPECT_NEAR(s.torque_noise[0].value, tau, 4 * s.torque_noise[0].se);
  EXPECT_NEAR(s.velocity_noise[0].se, vel / std::sqrt(2.0 * kRows), 0.05 * s.velocity_noise[0].se);
  const ImuEstimate& u = s.imus[0];
  ASSERT_TRUE(u.oriented);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(u.orientation_noise[k].value, orient, 4 * u.orientation_noise[k].se) << k;
  EXPECT_NEAR(u.orientation_noise_pooled.value, orient, 4 * u.orientation_noise_pooled.se);
  EXPECT_NEAR(u.orientation_noise_pooled.se, orient / std::sqrt(6.0 * kRows), 0.05 * u.orientation_noise_pooled.se);
  // the sway is what the gyro explains about x and z, not y
  EXPECT_GT(u.orientation_explained[0], 0.1);
  EXPECT_LT(u.orientation_explained[1], 0.01);
  // the velocity's 12 Hz swing (0.015 rad/s) is most of its high-passed variance: said
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_NE(s.warnings[0].find("dq_J"), std::string::npos) << s.warnings[0];
  std::printf("[ figures  ] velocity %.5g +- %.2g (truth %g), torque %.5g +- %.2g (%g), orientation "
              "%.4g %.4g %.4g pooled %.4g +- %.2g (%g), explained x %.3f y %.3f\n",
              s.velocity_noise[0].value, s.velocity_noise[0].se, vel, s.torque_noise[0].value,
              s.torque_noise[0].se, tau, u.orientation_noise[0].value, u.orientation_noise[1].value,
              u.orientation_noise[2].value, u.orientation_noise_pooled.value,
              u.orientation_noise_pooled.se, orient, u.orientation_explained[0], u.orientation_explained[1]);
  // the sensor file carries them
  const model::SensorParams p = SensorFileOf(s);
  EXPECT_EQ(p.encoders[0].velocity_noise, s.velocity_noise[0].value);
  EXPECT_EQ(p.encoders[0].torque_noise, s.torque_noise[0].value);
  EXPECT_EQ(p.imus[0].orientation_noise, u.orientation_noise_pooled.value);
}

TEST(MotionNoise, AMotionThatExplainsMostOfAChannelIsWarnedAbout) {
  SensorEstimates s;
  std::string error;
  // the torque's 12 Hz swing (500 N m/rad x 2e-4 rad) dwarfs its noise of 0.01 N m
  ASSERT_TRUE(EstimateSensors(WriteLog(2e-4, 0, 2e-3, 0.01, 5e-5), SensorOptions{}, &s, &error)) << error;
  bool warned = false;
  for (const std::string& w : s.warnings) warned |= w.find("tau_J") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_NEAR(s.torque_noise[0].value, 0.01, 4 * s.torque_noise[0].se);  // still found
}

TEST(MotionNoise, ATurningImuIsRefusedWithTheReason) {
  SensorEstimates s;
  std::string error;
  // 0.002 rad/s about x: 0.012 rad over the 6 s
  EXPECT_FALSE(EstimateSensors(WriteLog(2e-4, 2e-3, 2e-3, 0.3, 5e-5), SensorOptions{}, &s, &error));
  EXPECT_NE(error.find("I orientation about x moves"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::identify
