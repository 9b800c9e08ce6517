// Tests the base estimator (robot_model/estimator.h) on bad input: non-finite sensors are
// refused and the estimate kept, a Reset in the air puts the lower sole on the ground, a robot
// without the sensors it needs is refused.
#include "robot_model/estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "estimated_robot.h"

namespace ohrp::model {
namespace {

using testing::EstimatedRobot;
using testing::kControlPeriod;
using testing::kSettle;

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
