// Tests the base estimator (robot_model/estimator.h): HRP-1S standing on its soft soles in an
// in-process simulation (sim_host's scene, soft feet and servo, the segment's sensor block every
// 5 ms control cycle over 1 ms physics steps), the estimate compared with sim_truth every cycle
// while standing and while pushed; the complementary filter's tilt correction against its
// closed form. Bad input, a robot in the air and the preconditions are tested in
// estimator_input_test.cc; that Update allocates nothing in alloc_test.cc, the binary that
// counts allocations.
#include "robot_model/estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <ostream>
#include <string>

#include "estimated_robot.h"

namespace ohrp::model {
namespace {

using testing::EstimatedRobot;
using testing::ExpectWithinBounds;
using testing::kControlPeriod;
using testing::kDeg;
using testing::kSettle;

//---------------- standing and pushed, against sim_truth ----------------

TEST(BaseEstimator, TracksTheStandingRobotWhileItLeansAtTheAnkles) {
  // reset on the robot settled in the half-sitting pose at 3 s; the lean (0.06 rad at the
  // ankles from 3 s to 4 s) tilts the whole body forward and moves the base about 4 cm; then
  // 3 s standing
  EstimatedRobot r;
  r.Load(/*noise=*/false, /*lean_start=*/kSettle);
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  r.Reset();
  r.Run(4.0);
  if (::testing::Test::HasFatalFailure()) return;
  r.ExpectStanding();
  EXPECT_TRUE(r.estimator().estimate().contact[0] && r.estimator().estimate().contact[1]);
  ExpectWithinBounds(r.errors(), "standing, leaning at the ankles");
}

struct PushCase {
  const char* name;
  double impulse;  // [N s] over kPushDuration
  double direction_deg;  // in the world x-y plane, 0 = forward (+x), 90 = to the left (+y)
};
constexpr double kPushDuration = 0.1;  // [s]
void PrintTo(const PushCase& c, std::ostream* os) { *os << c.name; }

class Pushed : public ::testing::TestWithParam<PushCase> {};

TEST_P(Pushed, EstimateStaysWithinTheBounds) {
  const PushCase& c = GetParam();
  EstimatedRobot r;
  r.Load();
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  r.Reset();
  r.Run(0.5);
  const double a = c.direction_deg * kDeg;
  const Eigen::Vector3d force =
      c.impulse / kPushDuration * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
  r.Run(2.5, force, r.d()->time + kPushDuration);
  if (::testing::Test::HasFatalFailure()) return;
  r.ExpectStanding();
  ExpectWithinBounds(r.errors(), c.name);
}

INSTANTIATE_TEST_SUITE_P(
    BaseEstimator, Pushed,
    ::testing::Values(PushCase{"forward 15 N s", 15, 0}, PushCase{"forward 40 N s", 40, 0},
                      PushCase{"backward 40 N s", 40, 180}, PushCase{"sideways 15 N s", 15, 90},
                      PushCase{"sideways 40 N s", 40, 90}),
    [](const ::testing::TestParamInfo<PushCase>& info) {
      std::string n = info.param.name;
      for (char& ch : n)
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      return n;
    });

TEST(BaseEstimator, StaysWithinTheBoundsWithSensorNoise) {
  // sim_host's Gaussian noise at its defaults (docs/effects.md): q 1e-4 rad, dq 1e-3 rad/s,
  // force 1 N, gyro 5e-3 rad/s, accel 0.05 m/s^2. Reset takes roll and pitch from one
  // accelerometer sample, 0.05 / 9.81 rad = 0.3 deg of noise per axis, which the running mean
  // that starts the correction removes within 0.2 s; the record starts after 0.5 s (the
  // start-up is reported). Then standing, and a 40 N s push forward.
  EstimatedRobot r;
  r.Load(/*noise=*/true);
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  r.Reset();
  r.Run(0.5);
  if (::testing::Test::HasFatalFailure()) return;
  std::printf("[ figures  ] noisy sensors, start-up (0.5 s from Reset): %s\n", r.errors().Text().c_str());
  r.StartRecord();
  r.Run(0.5);
  r.Run(2.5, Eigen::Vector3d(400, 0, 0), r.d()->time + kPushDuration);
  if (::testing::Test::HasFatalFailure()) return;
  r.ExpectStanding();
  ExpectWithinBounds(r.errors(), "noisy sensors, after the start-up, forward 40 N s");
}

//---------------- the complementary filter ----------------

TEST(BaseEstimator, TiltErrorIsAveragedAwayThenDecaysAtTheFilterCrossover) {
  // a robot at rest (the settled sensor block, gyro and joint velocities zeroed) started on
  // one accelerometer sample tilted by delta0 = 2 deg, then given the true sample. The gravity
  // measurement passes a first-order low-pass (time constant tau_g = 1 / (2 pi 5 Hz)), so the
  // correction acts behind a delay D = tau_g (the low-pass) + dt / 2 (the specific force
  // averaged over the cycle) + dt / 2 (the correction's Euler step) = 7.4 cycles:
  //   - first the running mean in which the Reset's sample weighs N = 20 samples: after n
  //     updates delta = delta0 N / (N + n - D / dt) (the delay taken as a shift of the samples;
  //     within 1 % at n = 100, where the shift is 6 % of N + n),
  //   - then the complementary filter of gain k = tilt_gain, e' = -k e(t - D), which decays
  //     at the rate k (1 + k D) to first order in k D; the next term, 2 (k tau_g)^2, is 5e-4
  //     of the rate; the fast pole of the low-pass has decayed by exp(-20) when the
  //     comparison starts.
  //   Small angles throughout (sin(delta) = delta within 0.02 %).
  EstimatedRobot r;
  r.Load();
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  shm::SensorBlock rest = r.sensors();
  for (int i = 0; i < 3; ++i) rest.imu[0].gyro[i] = 0;
  for (int j = 0; j < r.kin().njoint(); ++j) rest.dq[j] = 0;

  BaseEstimator& est = r.estimator();
  ASSERT_TRUE(est.Reset(rest));
  const Eigen::Vector3d z_ref = est.estimate().quat_WB * Eigen::Vector3d::UnitZ();
  shm::SensorBlock tilted = rest;
  const double delta0 = 2 * kDeg;
  Eigen::Map<Eigen::Vector3d> accel(tilted.imu[0].accel);
  const Eigen::Vector3d axis = accel.cross(Eigen::Vector3d::UnitX()).normalized();
  accel = Eigen::AngleAxisd(delta0, axis) * accel;
  ASSERT_TRUE(est.Reset(tilted));

  const EstimatorOptions o;
  const double k = o.tilt_gain, dt = kControlPeriod;
  const double tau_g = 1 / (2 * M_PI * 5.0), weight = 20;
  auto tilt = [&] {
    const Eigen::Vector3d z = est.estimate().quat_WB * Eigen::Vector3d::UnitZ();
    return std::atan2(z.cross(z_ref).norm(), z.dot(z_ref));
  };
  EXPECT_NEAR(tilt(), delta0, 1e-6);
  int n = 0;
  for (; n < 100; ++n) ASSERT_TRUE(est.Update(rest, dt));
  const double delay = tau_g + dt;
  const double mean = delta0 * weight / (weight + n - delay / dt);
  EXPECT_NEAR(tilt() / mean, 1.0, 0.01) << "the running mean";

  const int n0 = static_cast<int>(std::lround(1 / (k * dt)));  // 400 cycles: k t = 1
  for (; n < 2 * n0; ++n) ASSERT_TRUE(est.Update(rest, dt));
  const double e1 = tilt();
  for (; n < 3 * n0; ++n) ASSERT_TRUE(est.Update(rest, dt));
  const double decay = std::exp(-k * (1 + k * delay) * n0 * dt);
  EXPECT_NEAR(tilt() / e1 / decay, 1.0, 0.0015) << "decay at the crossover";
}

}  // namespace
}  // namespace ohrp::model
