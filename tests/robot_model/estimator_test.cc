// Tests the base estimator (robot_model/estimator.h): HRP-1S standing on its soft soles in an
// in-process simulation (sim_host's scene, soft feet and servo, the segment's sensor block every
// 5 ms control cycle over 1 ms physics steps), the estimate compared with sim_truth every cycle
// while standing and while pushed; the complementary filter's tilt correction against its
// closed form; bad input and a robot in the air. (That Update allocates nothing is tested in
// alloc_test.cc, the binary that counts allocations.)
#include "robot_model/estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <ostream>
#include <string>

#include "../sim_host/leaning_robot.h"
#include "../sim_host/test_models.h"
#include "sim_host/effects.h"

namespace ohrp::model {
namespace {

constexpr double kControlPeriod = 0.005;  // [s] the segment's cycle
constexpr int kStepsPerCycle = 5;         // 1 ms physics steps (the scene's)
constexpr double kLean = -0.06;           // [rad] ankle lean of hrp1s_halfsit_lean.yaml: the
                                          // load centre under the middle of the soles
constexpr double kSettle = 3.0;           // [s] settling before a Reset (the robot at rest)
constexpr double kDeg = M_PI / 180;
// the issue's bounds, and "a few mm" for the horizontal drift over a run
constexpr double kTiltTolerance = 0.5 * kDeg;   // [rad]
constexpr double kHeightTolerance = 0.005;      // [m]
constexpr double kHorizontalTolerance = 0.005;  // [m]

// the largest errors of a run
struct Errors {
  double tilt = 0;        // angle between estimated and true base z axes [rad]
  double height = 0;      // base height [m]
  double horizontal = 0;  // base x-y displacement since the Reset [m]
  double velocity = 0;    // base linear velocity [m/s]
  double velocity_mean = 0;  // its mean over the run [m/s]
  double accel = 0;       // largest true base acceleration (over a cycle) [m/s^2]
  double angular = 0;     // base angular velocity [rad/s]
  long cycles = 0;
  std::string Text() const {
    char buf[300];
    std::snprintf(buf, sizeof(buf),
                  "tilt %.3f deg, height %.2f mm, horizontal %.2f mm, velocity %.1f mm/s "
                  "(mean %.1f mm/s; base acceleration up to %.2f m/s^2), angular velocity "
                  "%.2g rad/s over %ld cycles",
                  tilt / kDeg, height * 1e3, horizontal * 1e3, velocity * 1e3,
                  velocity_mean * 1e3, accel, angular, cycles);
    return buf;
  }
};

Eigen::Quaterniond Quat(const double* q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

// HRP-1S leaned at the ankles on its soft soles (tests/sim_host/leaning_robot.h), the
// segment's sensor block every control cycle, the estimator on its own kinematics
class EstimatedRobot {
 public:
  void Load(bool noise = false, double lean_start = 0) {
    sim_.Load("mjcf/hrp1s/scene_flat.xml", "halfsit", 0, kLean, 1.0);
    if (::testing::Test::HasFatalFailure()) return;
    sim_.set_lean_start(lean_start);
    ASSERT_NEAR(sim_.m()->opt.timestep * kStepsPerCycle, kControlPeriod, 1e-12);
    std::string error;
    kin_ = Kinematics::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &error);
    ASSERT_TRUE(kin_) << error;
    est_ = std::make_unique<BaseEstimator>(kin_.get());
    if (noise) noise_ = std::make_unique<sim::SensorNoise>(sim::NoiseOptions{}, SensorSelection{});
  }

  // one control cycle: the physics steps with `push` [N] on the base (world frame, at its
  // origin), then the sensor block
  void Cycle(const Eigen::Vector3d& push = Eigen::Vector3d::Zero()) {
    mjData* d = sim_.d();
    const int base = sim_.robot().base_body;
    for (int k = 0; k < kStepsPerCycle; ++k) {
      for (int i = 0; i < 3; ++i) d->xfrc_applied[6 * base + i] = push[i];
      ASSERT_TRUE(sim_.Step());
    }
    for (int i = 0; i < 3; ++i) d->xfrc_applied[6 * base + i] = 0;
    FillSensors(sim_.robot(), sim_.m(), d, &s_);
    if (noise_) noise_->Apply(sim_.robot(), &s_);
  }

  void Settle(double duration) {
    while (sim_.d()->time < duration - 1e-9) {
      Cycle();
      if (::testing::Test::HasFatalFailure()) return;
    }
  }

  // starts the estimator and the error record from the current state
  void Reset() {
    ASSERT_TRUE(est_->Reset(s_));
    StartRecord();
  }

  // starts the error record afresh (the estimator runs on)
  void StartRecord() {
    p0_est_ = est_->estimate().p_WB;
    p0_true_ = Eigen::Vector3d(s_.sim_truth.p_WB);
    errors_ = Errors{};
    Compare();
  }

  // `duration` [s] of cycles with `push` on while time < push_end
  void Run(double duration, const Eigen::Vector3d& push = Eigen::Vector3d::Zero(),
           double push_end = 0) {
    const double end = sim_.d()->time + duration - 1e-9;
    while (sim_.d()->time < end) {
      Cycle(sim_.d()->time < push_end - 1e-9 ? push : Eigen::Vector3d::Zero());
      if (::testing::Test::HasFatalFailure()) return;
      ASSERT_TRUE(est_->Update(s_, kControlPeriod)) << "at t = " << sim_.d()->time;
      Compare();
    }
  }

  // the robot still stands: base within 10 cm of its start, upright within 10 deg
  void ExpectStanding() const {
    const Eigen::Vector3d p(s_.sim_truth.p_WB);
    const Eigen::Vector3d z = Quat(s_.sim_truth.quat_WB) * Eigen::Vector3d::UnitZ();
    ASSERT_LT((p - p0_true_).norm(), 0.1) << "the robot left its place: the push is too strong";
    ASSERT_GT(z.z(), std::cos(10 * kDeg)) << "the robot fell: the push is too strong";
  }

  const Errors& errors() const { return errors_; }
  BaseEstimator& estimator() { return *est_; }
  Kinematics& kin() { return *kin_; }
  const shm::SensorBlock& sensors() const { return s_; }
  mjData* d() const { return sim_.d(); }
  const RobotMap& robot() const { return sim_.robot(); }

 private:
  void Compare() {
    const BaseEstimate& e = est_->estimate();
    const shm::SimTruth& t = s_.sim_truth;
    const Eigen::Vector3d z_est = e.quat_WB * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d z_true = Quat(t.quat_WB) * Eigen::Vector3d::UnitZ();
    const double tilt = std::atan2(z_est.cross(z_true).norm(), z_est.dot(z_true));
    const Eigen::Vector3d p_true(t.p_WB), v_true(t.v_WB);
    const Eigen::Vector2d moved = (e.p_WB - p0_est_).head<2>() - (p_true - p0_true_).head<2>();
    const double dv = (e.v_WB - v_true).norm();
    errors_.tilt = std::max(errors_.tilt, tilt);
    errors_.height = std::max(errors_.height, std::abs(e.p_WB.z() - p_true.z()));
    errors_.horizontal = std::max(errors_.horizontal, moved.norm());
    errors_.velocity = std::max(errors_.velocity, dv);
    errors_.angular = std::max(errors_.angular, (e.w_WB - Eigen::Vector3d(t.w_WB)).norm());
    errors_.velocity_mean = (errors_.velocity_mean * errors_.cycles + dv) / (errors_.cycles + 1);
    if (errors_.cycles > 0)
      errors_.accel = std::max(errors_.accel, (v_true - v_prev_).norm() / kControlPeriod);
    v_prev_ = v_true;
    ++errors_.cycles;
  }

  sim::testing::LeaningRobot sim_;
  std::unique_ptr<Kinematics> kin_;
  std::unique_ptr<BaseEstimator> est_;
  std::unique_ptr<sim::SensorNoise> noise_;
  shm::SensorBlock s_{};
  Eigen::Vector3d p0_est_ = Eigen::Vector3d::Zero(), p0_true_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_prev_ = Eigen::Vector3d::Zero();
  Errors errors_;
};

// The velocity is low-passed at velocity_cutoff (time constant tau_v = 8 ms): a first-order
// lag behind a signal whose rate stays below A errs by at most A tau_v; on top of it the leg
// kinematics' own error, which kVelocityAllowance bounds (the soft soles move under the robot:
// they sink 0.2 mm and shear up to 0.6 mm as the load shifts within a push's ~0.1 s).
constexpr double kVelocityAllowance = 0.005;  // [m/s]

void ExpectWithinBounds(const Errors& e, const std::string& what) {
  std::printf("[ figures  ] %s: %s\n", what.c_str(), e.Text().c_str());
  EXPECT_LT(e.tilt, kTiltTolerance) << what << ": " << e.Text();
  EXPECT_LT(e.height, kHeightTolerance) << what << ": " << e.Text();
  EXPECT_LT(e.horizontal, kHorizontalTolerance) << what << ": " << e.Text();
  const double tau_v = 1 / (2 * M_PI * EstimatorOptions{}.velocity_cutoff);
  EXPECT_LT(e.velocity, e.accel * tau_v + kVelocityAllowance) << what << ": " << e.Text();
}

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

//---------------- bad input, no contact, allocation ----------------

TEST(BaseEstimator, NonFiniteSensorsAreRefusedAndTheEstimateKept) {
  EstimatedRobot r;
  r.Load();
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  r.Reset();
  r.Run(0.1);
  BaseEstimator& est = r.estimator();
  const BaseEstimate before = est.estimate();
  const Eigen::Vector3d p_kin = r.kin().p_WB();
  const int lf = r.kin().soles()[r.kin().left_sole()].force_sensor;
  // one field at a time: gyro, accelerometer, joint position and velocity, sole force
  const std::function<void(shm::SensorBlock&)> spoil[] = {
      [](shm::SensorBlock& b) { b.imu[0].gyro[1] = std::nan(""); },
      [](shm::SensorBlock& b) { b.imu[0].accel[2] = std::nan(""); },
      [](shm::SensorBlock& b) { b.q[3] = std::nan(""); },
      [](shm::SensorBlock& b) { b.dq[0] = std::nan(""); },
      [&](shm::SensorBlock& b) { b.force[lf].force[2] = std::nan(""); }};
  for (const auto& f : spoil) {
    shm::SensorBlock bad = r.sensors();
    f(bad);
    EXPECT_FALSE(est.Update(bad, kControlPeriod));
    EXPECT_FALSE(est.Reset(bad));
  }
  EXPECT_FALSE(est.Update(r.sensors(), 0.0)) << "dt must be positive";
  const BaseEstimate& after = est.estimate();
  EXPECT_EQ(after.p_WB, before.p_WB);
  EXPECT_EQ(after.v_WB, before.v_WB);
  EXPECT_EQ(after.quat_WB.coeffs(), before.quat_WB.coeffs());
  EXPECT_EQ(r.kin().p_WB(), p_kin) << "the kinematics must keep the last estimate";
  EXPECT_TRUE(est.Update(r.sensors(), kControlPeriod));
}

TEST(BaseEstimator, ResetInTheAirPutsTheLowerSoleOnTheGround) {
  // the settled block with the soles unloaded: a robot held in the air at rest (the
  // accelerometer still reads +g). Reset: no contact, orientation from gravity as on the
  // ground, the lower sole's bottom on z = 0; held still it stays there; set down, its soles
  // are anchored where the estimate puts them, without a jump
  EstimatedRobot r;
  r.Load();
  if (::testing::Test::HasFatalFailure()) return;
  r.Settle(kSettle);
  shm::SensorBlock ground = r.sensors();
  for (int i = 0; i < 3; ++i) ground.imu[0].gyro[i] = 0;
  for (int j = 0; j < r.kin().njoint(); ++j) ground.dq[j] = 0;
  // at rest the accelerometer reads g exactly (the settled block still carries a little of
  // the settling's acceleration, which dead reckoning in the air would integrate)
  Eigen::Map<Eigen::Vector3d> accel(ground.imu[0].accel);
  accel *= 9.81 / accel.norm();
  shm::SensorBlock air = ground;
  for (auto& f : air.force) std::memset(&f, 0, sizeof(f));

  BaseEstimator& est = r.estimator();
  ASSERT_TRUE(est.Reset(ground));
  const BaseEstimate on_ground = est.estimate();
  ASSERT_TRUE(on_ground.contact[0] && on_ground.contact[1]);
  ASSERT_TRUE(est.Reset(air));
  const BaseEstimate in_air = est.estimate();
  EXPECT_FALSE(in_air.contact[0] || in_air.contact[1]);
  EXPECT_LT(in_air.quat_WB.angularDistance(on_ground.quat_WB), 1e-9);
  const double z_lower = std::min(r.kin().p_WSole(r.kin().left_sole()).z(),
                                  r.kin().p_WSole(r.kin().right_sole()).z());
  EXPECT_NEAR(z_lower, 0.0, 1e-9);
  // both soles flat on the ground in the pose: the same height as standing, within 1 mm
  EXPECT_NEAR(in_air.p_WB.z(), on_ground.p_WB.z(), 1e-3);

  for (int i = 0; i < 200; ++i) ASSERT_TRUE(est.Update(air, kControlPeriod));
  EXPECT_LT((est.estimate().p_WB - in_air.p_WB).norm(), 1e-6) << "held still, it must stay";
  const Eigen::Vector3d before = est.estimate().p_WB;
  ASSERT_TRUE(est.Update(ground, kControlPeriod));
  EXPECT_TRUE(est.estimate().contact[0] && est.estimate().contact[1]);
  EXPECT_LT((est.estimate().p_WB - before).norm(), 1e-6);
  for (int side = 0; side < 2; ++side) {
    const int sole = side == 0 ? r.kin().left_sole() : r.kin().right_sole();
    EXPECT_LT((est.anchor(side) - r.kin().p_WSole(sole)).norm(), 1e-9);
  }

  // a robot in free fall (the accelerometer reads nothing) is taken as upright
  shm::SensorBlock falling = air;
  for (int i = 0; i < 3; ++i) falling.imu[0].accel[i] = 0;
  ASSERT_TRUE(est.Reset(falling));
  EXPECT_LT(est.estimate().quat_WB.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
}

//---------------- preconditions ----------------

// two legs on a free base, each with a sole; the sensors are appended per test
std::string TwoLegs(const std::string& sensors) {
  return R"(
<mujoco model="two_legs">
  <worldbody>
    <body name="base" pos="0 0 0.6">
      <freejoint/>
      <geom type="box" size="0.1 0.15 0.1" mass="10"/>
      <site name="imu"/>
      <body name="lfoot" pos="0 0.1 -0.5">
        <joint name="lj" type="hinge" axis="0 1 0"/>
        <site name="lf"/>
        <geom name="L_SOLE" type="box" size="0.1 0.05 0.01" pos="0 0 -0.09" mass="1"/>
      </body>
      <body name="rfoot" pos="0 -0.1 -0.5">
        <joint name="rj" type="hinge" axis="0 1 0"/>
        <site name="rf"/>
        <geom name="R_SOLE" type="box" size="0.1 0.05 0.01" pos="0 0 -0.09" mass="1"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="lj" ctrlrange="-100 100" ctrllimited="true"/>
    <motor joint="rj" ctrlrange="-100 100" ctrllimited="true"/>
  </actuator>
  <sensor>)" + sensors + R"(</sensor>
</mujoco>)";
}
constexpr const char* kImu = R"(<gyro site="imu"/><accelerometer site="imu"/>)";
constexpr const char* kFeetFT =
    R"(<force site="lf"/><torque site="lf"/><force site="rf"/><torque site="rf"/>)";

std::unique_ptr<Kinematics> LoadInline(const std::string& xml) {
  std::string error;
  const std::string path = sim::testing::WriteTemp(xml);
  auto kin = Kinematics::Load(path, &error);
  std::remove(path.c_str());
  EXPECT_TRUE(kin) << error;
  return kin;
}

TEST(BaseEstimator, RefusesARobotWithoutTheSensorsItNeeds) {
  auto complete = LoadInline(TwoLegs(std::string(kImu) + kFeetFT));
  ASSERT_TRUE(complete);
  EXPECT_NO_THROW(BaseEstimator{complete.get()});

  auto no_imu = LoadInline(TwoLegs(kFeetFT));
  ASSERT_TRUE(no_imu);
  try {
    BaseEstimator e(no_imu.get());
    ADD_FAILURE() << "no IMU accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no IMU"), std::string::npos) << e.what();
  }

  auto no_ft = LoadInline(TwoLegs(kImu));
  ASSERT_TRUE(no_ft);
  try {
    BaseEstimator e(no_ft.get());
    ADD_FAILURE() << "soles without F/T sensors accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("force/torque sensor"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace ohrp::model
