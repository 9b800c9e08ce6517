// The base estimator tests' robot: HRP-1S leaned at the ankles on its soft soles in an
// in-process simulation (tests/sim_host/leaning_robot.h), the segment's sensor block every 5 ms
// control cycle over 1 ms physics steps, the estimator on its own kinematics, and the largest
// errors of a run against sim_truth with the bounds. Used by estimator_test.cc and
// estimator_input_test.cc.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>

#include "../sim_host/leaning_robot.h"
#include "../sim_host/test_models.h"
#include "robot_model/estimator.h"
#include "sim_host/effects.h"

namespace ohrp::model::testing {

inline constexpr double kControlPeriod = 0.005;  // [s] the segment's cycle
inline constexpr int kStepsPerCycle = 5;         // 1 ms physics steps (the scene's)
inline constexpr double kLean = -0.06;           // [rad] ankle lean of hrp1s_halfsit_lean.yaml: the
                                          // load centre under the middle of the soles
inline constexpr double kSettle = 3.0;           // [s] settling before a Reset (the robot at rest)
inline constexpr double kDeg = M_PI / 180;
// the bounds, and "a few mm" for the horizontal drift over a run
inline constexpr double kTiltTolerance = 0.5 * kDeg;   // [rad]
inline constexpr double kHeightTolerance = 0.005;      // [m]
inline constexpr double kHorizontalTolerance = 0.005;  // [m]

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

inline Eigen::Quaterniond Quat(const double* q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

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
    if (noise) noise_ = std::make_unique<SensorModel>(sim::NoiseAsSensorParams(sim::NoiseOptions{}, sim_.robot()), 1);
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
    if (noise_) sim::ApplySensorModel(sim_.robot(), SensorSelection{}, noise_.get(), &s_);
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
  std::unique_ptr<SensorModel> noise_;  // --effects noise=on's
  shm::SensorBlock s_{};
  Eigen::Vector3d p0_est_ = Eigen::Vector3d::Zero(), p0_true_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_prev_ = Eigen::Vector3d::Zero();
  Errors errors_;
};

// The velocity is low-passed at velocity_cutoff (time constant tau_v = 8 ms): a first-order
// lag behind a signal whose rate stays below A errs by at most A tau_v; on top of it the leg
// kinematics' own error, which kVelocityAllowance bounds (the soft soles move under the robot:
// they sink 0.2 mm and shear up to 0.6 mm as the load shifts within a push's ~0.1 s).
inline constexpr double kVelocityAllowance = 0.005;  // [m/s]

inline void ExpectWithinBounds(const Errors& e, const std::string& what) {
  std::printf("[ figures  ] %s: %s\n", what.c_str(), e.Text().c_str());
  EXPECT_LT(e.tilt, kTiltTolerance) << what << ": " << e.Text();
  EXPECT_LT(e.height, kHeightTolerance) << what << ": " << e.Text();
  EXPECT_LT(e.horizontal, kHorizontalTolerance) << what << ": " << e.Text();
  const double tau_v = 1 / (2 * M_PI * EstimatorOptions{}.velocity_cutoff);
  EXPECT_LT(e.velocity, e.accel * tau_v + kVelocityAllowance) << what << ": " << e.Text();
}

}  // namespace ohrp::model::testing
