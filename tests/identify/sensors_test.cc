// ohrp identify --sensors and the bandwidth: each estimator against a closed form. Synthetic
// signals of known bias and white noise (N samples: each estimate within 4 of its standard
// errors), a moving signal refused, and the -3 dB frequency of a first-order lag (1 / (2 pi tau))
// and of a Butterworth second-order servo (its natural frequency) recovered from a chirp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "identify/sensors.h"
#include "common/scratch.h"

namespace ohrp::identify {
namespace {

std::vector<double> Noise(size_t n, double bias, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  std::vector<double> x(n);
  for (double& v : x) v = bias + normal(rng);
  return x;
}

TEST(SensorEstimators, BiasAndNoiseOfWhiteNoiseWithinFourStandardErrors) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const double bias = 0.01 * seed, sigma = 0.003 * seed;
    const std::vector<double> x = Noise(5000, bias, sigma, seed);
    const Stat m = MeanOf(x), s = NoiseStd(x, 51);
    // the standard errors themselves: sigma / sqrt(N) and sigma / sqrt(2 N), within 40 % (the
    // batch means' from 20 blocks)
    EXPECT_NEAR(m.se, sigma / std::sqrt(5000.0), 0.4 * sigma / std::sqrt(5000.0));
    EXPECT_NEAR(s.se, sigma / std::sqrt(2 * 4950.0), 0.05 * s.se);
    EXPECT_NEAR(m.value, bias, 4 * m.se) << seed;
    EXPECT_NEAR(s.value, sigma, 4 * s.se) << seed;
  }
}

TEST(SensorEstimators, TheNoiseIsFoundUnderASlowDrift) {
  // a drift of 0.05 over the log (a slow sway) under noise 0.002: the moving average takes it out
  std::vector<double> x = Noise(5000, 0.0, 0.002, 7);
  for (size_t k = 0; k < x.size(); ++k) x[k] += 0.05 * std::sin(2 * M_PI * k / 5000.0);
  const Stat s = NoiseStd(x, 51);
  EXPECT_NEAR(s.value, 0.002, 4 * s.se);
  EXPECT_NEAR(SlowRange(x, 51), 0.1, 0.01);
}

// a data log as hw_driver --log writes it: one joint, one F/T, one IMU (with its orientation:
// tilted by `tilt` about x), `move` a slow motion of the joint
std::string WriteLog(double tilt, double move) {
  const std::string path = ohrp::testing::ScratchPath("still", ".csv");
  std::ofstream f(path);
  f << "time,q_J,qref_J,tau_J,F_fx,F_fy,F_fz,F_tx,F_ty,F_tz,I_gx,I_gy,I_gz,I_ax,I_ay,I_az,I_qw,I_qx,"
       "I_qy,I_qz,status\n";
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  const double g = 9.81, c = std::cos(tilt / 2), s = std::sin(tilt / 2);
  for (int k = 0; k < 4000; ++k) {
    const double t = 0.001 * k;
    f << t << "," << 0.3 + 1e-4 * n(rng) + move * t << ",0.3,1," << 1 + 0.5 * n(rng) << ","
      << 0.5 * n(rng) << "," << 300 + 0.8 * n(rng) << "," << 0.05 * n(rng) << "," << 0.05 * n(rng)
      << "," << 0.02 * n(rng) << "," << 0.01 + 0.002 * n(rng) << "," << -0.02 + 0.002 * n(rng) << ","
      << 0.005 + 0.002 * n(rng) << ","
      // R^T (0, 0, g) for a rotation by `tilt` about x: (0, g sin tilt, g cos tilt), plus the
      // bias (0.05, -0.1, 0.2)
      << 0.05 + 0.02 * n(rng) << "," << g * std::sin(tilt) - 0.1 + 0.02 * n(rng) << ","
      << g * std::cos(tilt) + 0.2 + 0.02 * n(rng) << "," << c << "," << s << ",0,0,0\n";
  }
  return path;
}

TEST(SensorEstimators, AStillLogsBiasAndNoise) {
  SensorEstimates s;
  std::string error;
  ASSERT_TRUE(EstimateSensors(WriteLog(0.1, 0), SensorOptions{}, &s, &error)) << error;
  ASSERT_EQ(s.joints.size(), 1u);
  ASSERT_EQ(s.imus.size(), 1u);
  ASSERT_EQ(s.ft_noise.size(), 6u);
  EXPECT_NEAR(s.encoder_noise[0].value, 1e-4, 4 * s.encoder_noise[0].se);
  const double ft[6] = {0.5, 0.5, 0.8, 0.05, 0.05, 0.02};
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(s.ft_noise[k].value, ft[k], 4 * s.ft_noise[k].se) << k;
  const ImuEstimate& u = s.imus[0];
  const double gyro[3] = {0.01, -0.02, 0.005}, accel[3] = {0.05, -0.1, 0.2};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(u.gyro_bias[k].value, gyro[k], 4 * u.gyro_bias[k].se) << k;
    EXPECT_NEAR(u.gyro_noise[k].value, 0.002, 4 * u.gyro_noise[k].se) << k;
    EXPECT_NEAR(u.accel_noise[k].value, 0.02, 4 * u.accel_noise[k].se) << k;
    ASSERT_TRUE(u.oriented);
    EXPECT_NEAR(u.accel_bias[k].value, accel[k], 4 * u.accel_bias[k].se) << k;
  }
  // along gravity: |R^T g + b| - g = b . (0, sin, cos) to first order
  const double along = std::sqrt(0.05 * 0.05 + std::pow(9.81 * std::sin(0.1) - 0.1, 2) +
                                 std::pow(9.81 * std::cos(0.1) + 0.2, 2)) - 9.81;
  EXPECT_NEAR(u.accel_bias_along_g.value, along, 4 * u.accel_bias_along_g.se);
}

TEST(SensorEstimators, AMovingJointIsRefusedWithTheReason) {
  SensorEstimates s;
  std::string error;
  EXPECT_FALSE(EstimateSensors(WriteLog(0, 0.01), SensorOptions{}, &s, &error));  // 0.04 rad in 4 s
  EXPECT_NE(error.find("joint J moves"), std::string::npos) << error;
  EXPECT_EQ(std::system((std::string(OHRP_BIN_DIR) + "/ohrp_identify --sensors " +
                         WriteLog(0, 0.01) + " --out " + ohrp::testing::ScratchFolder("refused") +
                         " >/dev/null 2>&1").c_str()), 2 << 8);
}

// a chirp 0.2 .. f1 Hz on the reference through a servo (one step of `step` per 1 ms)
template <class Step>
JointLog Chirp(double f1, double duration, Step step) {
  JointLog l;
  l.joint = "J";
  const double dt = 1e-3, f0 = 0.2;
  for (double t = 0; t < duration; t += dt) {
    const double phase = 2 * M_PI * (f0 * t + 0.5 * (f1 - f0) / duration * t * t);
    const double ref = 0.1 * std::sin(phase);
    l.t.push_back(t), l.ref.push_back(ref), l.q.push_back(step(ref, dt));
  }
  return l;
}

TEST(Bandwidth, AFirstOrderLagsMinus3dBIsOneOverTwoPiTau) {
  const double fc = 3.0, tau = 1 / (2 * M_PI * fc);
  double q = 0;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 2e-4);  // encoder noise
  const JointLog l = Chirp(10, 40, [&](double ref, double dt) {
    q += (1 - std::exp(-dt / tau)) * (ref - q);
    return q + n(rng);
  });
  Bandwidth b;
  std::string error;
  ASSERT_TRUE(EstimateBandwidth(l, &b, &error)) << error;
  ASSERT_TRUE(b.found);
  std::printf("[ figures  ] first order: %.4f +- %.4f Hz (the line's alone %.4f; truth %.4f), "
              "gain0 %.4f\n", b.f, b.f_se, b.f_fit_se, fc, b.gain0);
  EXPECT_NEAR(b.f, fc, 0.03 * fc);
  EXPECT_GT(b.f_se, 0);
  EXPECT_NEAR(b.f, fc, 3 * b.f_se);
  EXPECT_NEAR(b.gain0, 1.0, 0.1);  // its lowest windows: 0.6 Hz and the start's transient
}

TEST(Bandwidth, AButterworthServosMinus3dBIsItsNaturalFrequency) {
  // q'' = wn^2 (ref - q) - 2 zeta wn q', zeta = 1/sqrt(2): |H| = 1/sqrt(2) at wn exactly
  const double fn = 2.0, wn = 2 * M_PI * fn, zeta = 1 / std::sqrt(2.0);
  double q = 0, v = 0;
  const JointLog l = Chirp(6, 40, [&](double ref, double dt) {
    for (int i = 0; i < 10; ++i) {  // semi-implicit Euler at dt / 10
      v += dt / 10 * (wn * wn * (ref - q) - 2 * zeta * wn * v);
      q += dt / 10 * v;
    }
    return q;
  });
  Bandwidth b;
  std::string error;
  ASSERT_TRUE(EstimateBandwidth(l, &b, &error)) << error;
  ASSERT_TRUE(b.found);
  std::printf("[ figures  ] Butterworth: %.4f +- %.4f Hz (the line's alone %.4f; truth %.4f)\n",
              b.f, b.f_se, b.f_fit_se, fn);
  EXPECT_NEAR(b.f, fn, 0.03 * fn);
  EXPECT_NEAR(b.f, fn, 3 * b.f_se);
}

TEST(Bandwidth, AServoFasterThanTheChirpIsReportedAbove) {
  const double tau = 1 / (2 * M_PI * 20.0);
  double q = 0;
  const JointLog l = Chirp(5, 20, [&](double ref, double dt) {
    return q += (1 - std::exp(-dt / tau)) * (ref - q);
  });
  Bandwidth b;
  std::string error;
  ASSERT_TRUE(EstimateBandwidth(l, &b, &error)) << error;
  EXPECT_FALSE(b.found);
  EXPECT_GT(b.f_max, 4.0);
}

}  // namespace
}  // namespace ohrp::identify
