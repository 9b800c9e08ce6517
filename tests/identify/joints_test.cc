// Tests ohrp identify --joints (identify/joints.h) against a closed form: one hinge of known
// inertia, viscous and Coulomb friction and gravity, under a PD servo of known gains whose
// references arrive a known number of cycles late, driven by excite's chirp, integrated finely.
#include "identify/joints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>

#include "common/scratch.h"
#include "controllers/excite.h"

namespace ohrp::identify {
namespace {

struct Hinge {
  double inertia = 0.5, viscous = 0.3, coulomb = 0.4;  // [kg m^2], [N m s/rad], [N m]
  double gravity = 3.0, gravity_phase = 0.2;           // tau_g = gravity sin(q - phase)
  double kp = 200, kd = 10;
  int delay = 4;                                       // [cycles] of the references
};

// excite's chirp on the hinge: 1 ms cycles of one physics step (as hw_emulator's boards: the
// torque logged is the one that moved the joint to the state logged with it), excite's log
JointLog Simulate(const Hinge& h, double amplitude) {
  controllers::ExciteOptions o;
  o.amplitude = amplitude, o.f_min = 0.2, o.f_max = 2.0, o.duration = 12.0;
  const std::vector<int8_t> none;
  constexpr double kCycle = 0.001;
  constexpr int kSteps = 1;
  const double dt = kCycle / kSteps;
  JointLog l;
  l.joint = std::string(1, 'J');  // (not = "J": GCC 12 warns -Wrestrict wrongly there)
  std::vector<double> refs;
  double q = 0, dq = 0, tau = 0;
  const int cycles = static_cast<int>(o.duration / kCycle);
  for (int k = 0; k < cycles; ++k) {
    const double t = k * kCycle;
    const double ref = amplitude * ExciteSignalValue(controllers::ExciteSignal::kChirp, o, none, t);
    l.t.push_back(t), l.ref.push_back(ref), l.q.push_back(q), l.dq.push_back(dq), l.tau.push_back(tau);
    refs.push_back(ref);
    // the reference of `delay` cycles ago, its rate as excite commands it
    const int j = k - h.delay;
    const double r = j >= 0 ? refs[j] : 0, r_prev = j >= 1 ? refs[j - 1] : 0;
    const double dr = j >= 1 ? (r - r_prev) / kCycle : 0;
    for (int s = 0; s < kSteps; ++s) {
      tau = h.kp * (r - q) + h.kd * (dr - dq);
      const double friction = h.viscous * dq + h.coulomb * std::tanh(dq / 1e-3);
      const double qdd = (tau - friction - h.gravity * std::sin(q - h.gravity_phase)) / h.inertia;
      dq += qdd * dt;  // semi-implicit Euler
      q += dq * dt;
    }
  }
  return l;
}

TEST(JointIdentification, RecoversInertiaFrictionGainsAndDelayOfAKnownHinge) {
  const Hinge h;
  const JointLog l = Simulate(h, 0.3);
  JointEstimate e;
  std::string error;
  ASSERT_TRUE(EstimateJoint(l, JointFitOptions{}, &e, &error)) << error;
  std::printf("[ figures  ] hinge: I %.4f +- %.4f (true 0.5), b %.4f +- %.4f (0.3), c %.4f +- "
              "%.4f (0.4) from %zu moving samples of %zu (residual %.4f N m of %.3f); lag %d "
              "cycles (delay 4 + the loop's 1), kp %.2f (200), kd %.3f (10)\n",
              e.inertia, e.inertia_se, e.viscous, e.viscous_se, e.coulomb, e.coulomb_se,
              e.moving, e.samples, e.dynamics_rms, e.tau_rms, e.lag_cycles, e.kp, e.kd);
  EXPECT_NEAR(e.inertia, h.inertia, 1e-3 * h.inertia);
  EXPECT_NEAR(e.viscous, h.viscous, 1e-3 * h.viscous);
  EXPECT_NEAR(e.coulomb, h.coulomb, 1e-3 * h.coulomb);
  // the logged torque is the last physics step's of the previous cycle: one cycle more
  EXPECT_EQ(e.lag_cycles, h.delay + 1);
  EXPECT_NEAR(e.lag, 0.005, 1e-9);
  EXPECT_NEAR(e.kp, h.kp, 1e-3 * h.kp);
  EXPECT_NEAR(e.kd, h.kd, 1e-3 * h.kd);
}

// The bootstrap's standard errors (joints.h) cover the spread: the hinge's logged torque with
// white noise (0.5 N m, a sensor's) drawn with 8 seeds; each parameter's error within 3 of its
// stated standard error in every draw, and over all draws the errors' RMS in standard errors
// between 0.5 and 2 (the standard errors neither too small nor uselessly large).
TEST(JointIdentification, TheBootstrapStandardErrorsCoverTheNoisesSpread) {
  const Hinge h;
  const JointLog clean = Simulate(h, 0.3);
  constexpr double kNoise = 0.5;  // [N m]
  double sum2 = 0;
  int n = 0;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    JointLog l = clean;
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> noise(0.0, kNoise);
    for (double& t : l.tau) t += noise(rng);
    JointEstimate e;
    std::string error;
    ASSERT_TRUE(EstimateJoint(l, JointFitOptions{}, &e, &error)) << error;
    const struct {
      const char* name;
      double value, se, truth;
    } p[] = {{"I", e.inertia, e.inertia_se, h.inertia}, {"b", e.viscous, e.viscous_se, h.viscous},
             {"c", e.coulomb, e.coulomb_se, h.coulomb}, {"kp", e.kp, e.kp_se, h.kp},
             {"kd", e.kd, e.kd_se, h.kd}};
    std::printf("[ figures  ] seed %u:", seed);
    for (const auto& x : p) {
      ASSERT_GT(x.se, 0) << x.name;
      const double z = (x.value - x.truth) / x.se;
      std::printf(" %s %.5g +- %.2g (%+.2f se)", x.name, x.value, x.se, z);
      EXPECT_LE(std::fabs(z), 3.0) << x.name << " seed " << seed;
      sum2 += z * z;
      ++n;
    }
    std::printf("; lag %d\n", e.lag_cycles);
    EXPECT_EQ(e.lag_cycles, h.delay + 1);
  }
  const double rms = std::sqrt(sum2 / n);
  std::printf("[ figures  ] over %d estimates the errors' RMS is %.2f of the stated se\n", n, rms);
  EXPECT_GT(rms, 0.5);
  EXPECT_LT(rms, 2.0);
}

TEST(JointIdentification, TheExciteLogIsReadAndTooLittleMotionIsRefused) {
  const JointLog l = Simulate(Hinge{}, 0.3);
  const std::string path = ohrp::testing::ScratchPath("excite", ".csv");
  {
    std::ofstream f(path);
    f << "time,J_ref,J_q,J_dq,J_tau,K_ref,K_q,K_dq,K_tau\n";
    for (size_t k = 0; k < l.t.size(); ++k)
      f << l.t[k] << "," << l.ref[k] << "," << l.q[k] << "," << l.dq[k] << "," << l.tau[k]
        << ",0,0,0,0\n";
  }
  std::vector<JointLog> joints;
  std::string error;
  ASSERT_TRUE(ReadExciteLog(path, &joints, &error)) << error;
  ASSERT_EQ(joints.size(), 2u);
  EXPECT_EQ(joints[0].joint, "J");
  EXPECT_EQ(joints[1].joint, "K");
  EXPECT_EQ(joints[0].t.size(), l.t.size());
  JointEstimate e;
  EXPECT_FALSE(EstimateJoint(joints[1], JointFitOptions{}, &e, &error));  // K never moved
  EXPECT_NE(error.find("K: 0 samples move faster"), std::string::npos) << error;
  const std::string bad = ohrp::testing::ScratchFile("bad", "time,a,b\n1,2,3\n", ".csv");
  EXPECT_FALSE(ReadExciteLog(bad, &joints, &error));
  EXPECT_NE(error.find("not an excite log"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::identify
