// ohrp identify --sensors on an emulated robot whose sensors differ from the model by values the
// identification is not told (hw_emulator --encoder-noise, --imu-bias, --imu-noise, --ft-noise):
// HRP-1S standing half-sitting on its boards, this test as the driver holding the pose (the udp
// plugin, as hw_driver), a data log written as hw_driver --log writes it (time, q_J, qref_J,
// tau_J, F_fx..tz, I_gx..az, I_qw..qz), fitted over its still window and compared with the truth.
#include <complex>
#include <cstdio>
#include <fstream>
#include <map>

#include "../hw_udp/emulator_fixture.h"
#include "elbow_inertia.h"
#include "controllers/excite.h"
#include "identify/sensors.h"

namespace ohrp::identify {
namespace {

using namespace hw::udp::emulator_test;  // NOLINT(build/namespaces): the emulator fixture

constexpr double kEncoderNoise = 2e-4;                          // [rad]
constexpr double kGyroBias[3] = {0.01, -0.02, 0.005};           // [rad/s]
constexpr double kAccelBias[3] = {0.05, -0.1, 0.2};             // [m/s^2]
constexpr double kGyroNoise = 0.003, kAccelNoise = 0.03;        // [rad/s], [m/s^2]
constexpr double kForceNoise = 2.0, kTorqueNoise = 0.1;         // [N], [N m]

class SensorsOnTheEmulator : public EmulatorTest {
 protected:
  // the driver holding the pose, every new board state a row of a data log as hw_driver --log
  // writes it (time, q_J, qref_J, tau_J, F_fx..tz, I_gx..az, I_qw..qz)
  void RecordStill(const std::string& csv, size_t* rows) {
    const Robot& r = Hrp1s();
    const size_t nj = r.config.joint_names.size(), nf = r.config.force_names.size(),
                 ni = r.config.imu_names.size();
    ASSERT_GE(ni, 1u);
    std::ofstream f(csv);
    f << "time";
    for (const char* p : {"q_", "qref_", "tau_"})
      for (const auto& j : r.config.joint_names) f << "," << p << j;
    for (const auto& n : r.config.force_names)
      for (const char* c : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) f << "," << n << c;
    for (const auto& n : r.config.imu_names)
      for (const char* c : {"_gx", "_gy", "_gz", "_ax", "_ay", "_az", "_qw", "_qx", "_qy", "_qz"})
        f << "," << n << c;
    f << "\n";
    f.precision(10);
    uint64_t last = 0;
    ASSERT_EQ(Drive([&](const hw::IoState& s, hw::IoCommand* c) {
                if (s.time_ns == last) return;  // no new state
                last = s.time_ns;
                ++*rows;
                f << s.time_ns * 1e-9;
                for (size_t j = 0; j < nj; ++j) f << "," << s.q[j];
                for (size_t j = 0; j < nj; ++j) f << "," << c->joint[j].q_ref;
                for (size_t j = 0; j < nj; ++j) f << "," << s.tau[j];
                for (size_t i = 0; i < nf; ++i) {
                  for (int k = 0; k < 3; ++k) f << "," << s.force[i].force[k];
                  for (int k = 0; k < 3; ++k) f << "," << s.force[i].torque[k];
                }
                for (size_t i = 0; i < ni; ++i) {
                  for (int k = 0; k < 3; ++k) f << "," << s.imu[i].gyro[k];
                  for (int k = 0; k < 3; ++k) f << "," << s.imu[i].accel[k];
                  for (int k = 0; k < 4; ++k) f << "," << s.imu[i].quat_WI[k];
                }
                f << "\n";
              }),
              0)
        << Stderr();
    f.close();
  }
};

TEST_F(SensorsOnTheEmulator, BiasAndNoiseAreRecovered) {
#ifdef OHRP_SANITIZE
  GTEST_SKIP() << "the emulator's boards run in real time: not in a sanitizer build";
#endif
  const int port = Start({"--duration", "7.5", "--keyframe", "halfsit", "--encoder-noise", "2e-4",
                          "--imu-bias", "0.01,-0.02,0.005,0.05,-0.1,0.2", "--imu-noise",
                          "0.003,0.03", "--ft-noise", "2,0.1"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  const std::string csv = ohrp::testing::ScratchPath("still", ".csv");
  size_t rows = 0;
  RecordStill(csv, &rows);
  SensorOptions o;
  // the pose held, the robot settled on its soles: the emulator's default soft soles (as
  // sim_host's) rock the standing robot longer than its native contact did (at 2 s the
  // accelerometer's slow part still spanned 0.052 m/s^2)
  o.from = 3.5;
  SensorEstimates e;
  std::string error;
  ASSERT_TRUE(EstimateSensors(csv, o, &e, &error)) << error << " (" << csv << ")";
  std::printf("[ figures  ] %zu still rows of %zu\n", e.samples, rows);
  double worst = 0;
  for (size_t j = 0; j < e.joints.size(); ++j)
    worst = std::fmax(worst, std::fabs(e.encoder_noise[j].value / kEncoderNoise - 1));
  std::printf("[ figures  ] encoder noise: %zu joints, worst relative error %.3f (truth %.1e, se "
              "%.1e)\n", e.joints.size(), worst, kEncoderNoise, e.encoder_noise[0].se);
  EXPECT_LT(worst, 0.1);
  for (size_t i = 0; i < e.forces.size(); ++i)
    for (int k = 0; k < 6; ++k) {
      const Stat& n = e.ft_noise[6 * i + k];
      const double truth = k < 3 ? kForceNoise : kTorqueNoise;
      std::printf("[ figures  ] %s axis %d noise %.4g +- %.2g (truth %.4g)\n", e.forces[i].c_str(),
                  k, n.value, n.se, truth);
      EXPECT_NEAR(n.value, truth, 0.1 * truth);
    }
  for (const ImuEstimate& u : e.imus) {
    for (int k = 0; k < 3; ++k) {
      std::printf("[ figures  ] %s axis %d: gyro bias %.5f +- %.5f (%.3f), noise %.5f (%.3f); "
                  "accel noise %.4f (%.3f), bias %.4f +- %.4f (%.3f)\n", u.name.c_str(), k,
                  u.gyro_bias[k].value, u.gyro_bias[k].se, kGyroBias[k], u.gyro_noise[k].value,
                  kGyroNoise, u.accel_noise[k].value, kAccelNoise, u.accel_bias[k].value,
                  u.accel_bias[k].se, kAccelBias[k]);
      EXPECT_NEAR(u.gyro_bias[k].value, kGyroBias[k], 1e-3);
      EXPECT_NEAR(u.gyro_noise[k].value, kGyroNoise, 0.1 * kGyroNoise);
      EXPECT_NEAR(u.accel_noise[k].value, kAccelNoise, 0.1 * kAccelNoise);
      ASSERT_TRUE(u.oriented);
      EXPECT_NEAR(u.accel_bias[k].value, kAccelBias[k], 0.02);
    }
    std::printf("[ figures  ] %s accel bias along gravity %.4f +- %.4f\n", u.name.c_str(),
                u.accel_bias_along_g.value, u.accel_bias_along_g.se);
  }
  // the same through the command line: ohrp_identify --sensors LOG --from 3.5 (exit 0, the json)
  const std::string out = ohrp::testing::ScratchFolder("identify");
  EXPECT_EQ(std::system((std::string(OHRP_BIN_DIR) + "/ohrp_identify --sensors " + csv +
                         " --from 3.5 --out " + out + " > " + out + "/stdout 2>&1").c_str()), 0);
  std::ifstream json(out + "/sensors.json");
  std::stringstream all;
  all << json.rdbuf();
  EXPECT_NE(all.str().find("\"gyro_bias_x\""), std::string::npos) << all.str();
  EXPECT_NE(all.str().find("not observable"), std::string::npos);
  std::ifstream text(out + "/stdout");
  std::stringstream printed;
  printed << text.rdbuf();
  std::printf("%s", printed.str().c_str());
}


// The F/T offsets and encoder biases on the rig (issue 35): HRP-1S hung (scene_hung.xml, keyframe
// rig: feet and hands in the air) on hw_emulator with --ft-bias, --ft-noise and --encoder-bias the
// fit is not told; --sensors --model against the model's static load of each sensor's subtree
// (identify/sensors_ft_bias.cc) and its gravity torques (sensors_encoder_bias.cc).
TEST_F(SensorsOnTheEmulator, ForceTorqueOffsetsOnTheRig) {
#ifdef OHRP_SANITIZE
  GTEST_SKIP() << "the emulator's boards run in real time: not in a sanitizer build";
#endif
  constexpr double kBias[6] = {1.5, -0.8, 4.0, 0.12, -0.3, 0.05};  // [N], [N m]
  const std::string hung = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_hung.xml";
  const int port = Start({"--duration", "6", "--keyframe", "rig", "--contact", "native", "--ft-bias",
                          "1.5,-0.8,4.0,0.12,-0.3,0.05", "--ft-noise", "1,0.05", "--encoder-bias",
                          "RLEG_KNEE=0.02", "--encoder-bias", "LARM_SHOULDER_P=-0.015",
                          "--encoder-bias", "LLEG_HIP_P=0.01"}, "30", hung);
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  const std::string csv = ohrp::testing::ScratchPath("hung", ".csv");
  size_t rows = 0;
  RecordStill(csv, &rows);
  SensorOptions o;
  o.from = 2.0;
  SensorEstimates e;
  std::string error;
  ASSERT_TRUE(EstimateSensors(csv, o, &e, &error)) << error << " (" << csv << ")";
  // the encoders' biases first: the F/T sensors' static loads are computed where the joints are
  JointModel rig;
  rig.model = hung, rig.keyframe = "rig";
  ASSERT_TRUE(EstimateEncoderBias(rig, o.min_gravity_stiffness, &e, &error)) << error;
  ASSERT_TRUE(EstimateForceBias(rig, o.gravity, &e, &error)) << error;
  std::printf("[ figures  ] %zu still rows of %zu\n", e.samples, rows);
  ASSERT_FALSE(e.forces.empty());
  for (size_t i = 0; i < e.forces.size(); ++i)
    for (int k = 0; k < 6; ++k) {
      const Stat& b = e.ft_bias[6 * i + k];
      std::printf("[ figures  ] %s axis %d offset %.4f +- %.4f (truth %.4f; static load %.4f)\n",
                  e.forces[i].c_str(), k, b.value, b.se, kBias[k], e.ft_expected[6 * i + k]);
      // within 4 standard errors and a floor for the model's residual (5e-4 N noise-free)
      EXPECT_NEAR(b.value, kBias[k], 4 * b.se + 1e-3) << e.forces[i] << " axis " << k;
    }
  // the encoder biases against the model's gravity torque: the three biased joints within 10 %
  // (first order in the bias: the gravity stiffness changes over it) and 4 standard errors; the
  // other observable joints within 1e-3 rad of 0
  const std::map<std::string, double> truth = {{"RLEG_KNEE", 0.02}, {"LARM_SHOULDER_P", -0.015},
                                               {"LLEG_HIP_P", 0.01}};
  for (size_t j = 0; j < e.joints.size(); ++j) {
    const auto it = truth.find(e.joints[j]);
    const double b = it == truth.end() ? 0.0 : it->second;
    if (!e.encoder_observable[j]) {
      EXPECT_EQ(b, 0.0) << e.joints[j] << " (stiffness " << e.gravity_stiffness[j] << ")";
      continue;
    }
    const Stat& x = e.encoder_bias[j];
    std::printf("[ figures  ] %s encoder bias %.5f +- %.5f (truth %.4f; gravity stiffness %.2f)\n",
                e.joints[j].c_str(), x.value, x.se, b, e.gravity_stiffness[j]);
    EXPECT_NEAR(x.value, b, 4 * x.se + 0.1 * std::fabs(b) + 1e-3) << e.joints[j];
  }
}

// The elbow with 100 kg m^2 of armature the fit is not told (its -3 dB brought down to about
// 3.4 Hz, where a 0.002 rad chirp needs about 100 N m of its 150) under a chirp 0.2-6 Hz:
// the bandwidth against the closed form of its servo, the board's PD on ref and its rate,
//   H(s) = (kd s + kp) / (I s^2 + kd s + kp)
// (the commands' delay does not change the magnitude; the gravity stiffness and the model's
// damping, small against kp and kd, are left out)
TEST_F(SensorsOnTheEmulator, TheElbowsBandwidthIsItsServosMinus3dB) {
#ifdef OHRP_SANITIZE
  GTEST_SKIP() << "the emulator's real-time excitation is not real time in a sanitizer build";
#endif
  int elbow = -1;
  const double inertia = testing::ModelElbowInertia(kScene, &elbow) + 100.0;
  const double kp = Hrp1s().kp[elbow], kd = Hrp1s().kd[elbow];
  double lo = 0.1, hi = 50;  // |H| falls through 1/sqrt(2) once above its peak
  for (int i = 0; i < 60; ++i) {
    const double f = 0.5 * (lo + hi);
    const std::complex<double> s(0, 2 * M_PI * f);
    (std::abs((kd * s + kp) / (inertia * s * s + kd * s + kp)) > 1 / std::sqrt(2.0) ? lo : hi) = f;
  }
  const double truth = lo;
  const int port = Start({"--duration", "23.0", "--keyframe", "halfsit", "--armature",
                          "LARM_ELBOW=100"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  controllers::ExciteOptions x;
  x.amplitude = 0.002, x.f_min = 0.2, x.f_max = 6.0, x.duration = 20.0;
  JointLog log;
  log.joint = "LARM_ELBOW";
  ASSERT_EQ(Drive(testing::ChirpInto(elbow, x, &log)), 0) << Stderr();
  Bandwidth b;
  std::string error;
  ASSERT_TRUE(EstimateBandwidth(log, &b, &error)) << error;
  double tau_max = 0;
  for (double t : log.tau) tau_max = std::fmax(tau_max, std::fabs(t));
  std::printf("[ figures  ] LARM_ELBOW (I %.2f kg m^2, kp %.0f, kd %.1f): bandwidth %s %.3f +- %.3f "
              "Hz (the line's %.3f; closed form %.3f Hz), gain0 %.4f, %zu windows, |tau| <= %.0f N m\n",
              inertia, kp, kd, b.found ? "" : "above", b.found ? b.f : b.f_max, b.f_se, b.f_fit_se,
              truth, b.gain0, b.freq.size(), tau_max);
  for (size_t i = 0; i < b.freq.size(); i += 4) {
    const std::complex<double> s(0, 2 * M_PI * b.freq[i]);
    std::printf("[ figures  ]   %.3f Hz: |q/ref| %.4f +- %.4f (closed form %.4f)\n", b.freq[i], b.mag[i],
                b.mag_se[i], std::abs((kd * s + kp) / (inertia * s * s + kd * s + kp)));
  }
  ASSERT_TRUE(b.found);
  EXPECT_NEAR(b.f, truth, 0.05 * truth);
  EXPECT_NEAR(b.f, truth, 3 * b.f_se);
}

}  // namespace
}  // namespace ohrp::identify
