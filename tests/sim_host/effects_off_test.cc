// Tests that an effect of sim_host/effects.h switched off is really off in MuJoCo (gravity,
// limits, passive forces, contact, sensors, mj_rnePostConstraint), and the sensor noise
// (standard deviation, seed, exact when off).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "effects_scenes.h"

namespace ohrp::sim {
namespace {

using testing::Apply;
using testing::kBoxes;
using testing::kFlat;
using testing::Load;
using testing::Loaded;
using testing::LoadText;
using testing::Resolve;

//---------------- switched off is really off ----------------

TEST(EffectsOff, GravityOffAFreeBodyDoesNotFall) {
  model::InstallMujocoHandlers(nullptr);
  for (bool gravity : {true, false}) {
    Loaded l = LoadText(kBoxes);
    mjModel* m = l.scene->m();
    mjData* d = l.scene->d();
    Apply(l, Resolve(l, gravity ? "native_contact=off" : "native_contact=off,gravity=off"));
    const int box = mj_name2id(m, mjOBJ_BODY, "box1");
    const double z0 = d->xpos[3 * box + 2];
    const int n = 200;  // 0.4 s
    for (int i = 0; i < n; ++i) mj_step(m, d);
    mj_forward(m, d);
    const double t = n * m->opt.timestep;
    if (gravity) {
      // semi-implicit Euler: z = z0 - g dt^2 n(n+1)/2, within 1 % of g t^2 / 2
      EXPECT_NEAR(z0 - d->xpos[3 * box + 2], 0.5 * 9.81 * t * t, 0.01 * 0.5 * 9.81 * t * t);
    } else {
      EXPECT_EQ(d->xpos[3 * box + 2], z0);  // exactly
    }
  }
}

TEST(EffectsOff, ContactOffPerPair) {
  model::InstallMujocoHandlers(nullptr);
  Loaded l = LoadText(kBoxes);
  mjModel* m = l.scene->m();
  mjData* d = l.scene->d();
  Apply(l, Resolve(l, "contact:box1/world=off"));
  for (int i = 0; i < 250; ++i) mj_step(m, d);  // 0.5 s
  const int b1 = mj_name2id(m, mjOBJ_BODY, "box1"), b2 = mj_name2id(m, mjOBJ_BODY, "box2");
  EXPECT_LT(d->xpos[3 * b1 + 2], -0.9);              // fell through: 0.1 - g 0.5^2 / 2 = -1.1
  EXPECT_NEAR(d->xpos[3 * b2 + 2], 0.1, 0.005);       // rests on the floor
  ClearContactFilter();
  // native contact off entirely: both fall
  Loaded l2 = LoadText(kBoxes);
  Apply(l2, Resolve(l2, "native_contact=off"));
  EXPECT_TRUE(l2.scene->m()->opt.disableflags & mjDSBL_CONTACT);
  for (int i = 0; i < 250; ++i) mj_step(l2.scene->m(), l2.scene->d());
  EXPECT_LT(l2.scene->d()->xpos[3 * b2 + 2], -0.9);
}

TEST(EffectsOff, JointLimitsOffTheJointPassesItsLimit) {
  model::InstallMujocoHandlers(nullptr);
  for (bool limits : {true, false}) {
    Loaded l = LoadText(testing::kTwoJointArm);
    Apply(l, Resolve(l, limits ? "" : "joint_limits=off"));
    mjData* d = l.scene->d();
    const int j1 = l.robot.joints[0].qpos_adr;
    for (int i = 0; i < 2000; ++i) {
      d->ctrl[0] = 20;  // pushes j1 to its limit at 1.5 rad
      mj_step(l.scene->m(), d);
    }
    if (limits) EXPECT_LT(d->qpos[j1], 1.55);
    else EXPECT_GT(d->qpos[j1], 2.0);  // 20 N m on 2 kg m^2 for 2 s: 20 rad unlimited
  }
}

TEST(EffectsOff, PassiveOffNoDamping) {
  model::InstallMujocoHandlers(nullptr);
  // a vertical hinge (no gravity torque) of rotor inertia 2 kg m^2 and damping 0.5 N m s
  constexpr const char* kDamped = R"(
<mujoco model="damped">
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <body name="rotor">
      <joint name="j" type="hinge" axis="0 0 1" armature="2" damping="0.5"/>
      <geom type="sphere" size="0.01" mass="1e-6" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator><motor joint="j"/></actuator>
</mujoco>
)";
  for (bool passive : {true, false}) {
    Loaded l = LoadText(kDamped);
    const EffectsPlan p = Resolve(l, passive ? "" : "passive=off");
    EXPECT_EQ(p.on(Effect::kPassive), passive);
    Apply(l, p);
    mjModel* m = l.scene->m();
    mjData* d = l.scene->d();
    d->qvel[0] = 1.0;
    const int n = 1000;
    for (int i = 0; i < n; ++i) mj_step(m, d);
    if (passive) {
      // Euler with implicit damping: v_n = v_0 / (1 + h b / I)^n, I = 2 (+ the sphere's 4e-11)
      const double expected = 1.0 / std::pow(1 + 0.001 * 0.5 / 2, n);
      EXPECT_NEAR(d->qvel[0], expected, 1e-3 * expected);
    } else {
      EXPECT_EQ(d->qvel[0], 1.0);  // no force at all
    }
  }
}

TEST(EffectsOff, SensorsOffAreNotComputed) {
  model::InstallMujocoHandlers(nullptr);
  constexpr double kSentinel = 12345.0;
  for (bool on : {true, false}) {
    Loaded l = Load(kFlat);
    mjModel* m = l.scene->m();
    mjData* d = l.scene->d();
    const EffectsPlan p = Resolve(l, on ? "" : "force_torque=off,accelerometer=off");
    EXPECT_EQ(p.on(Effect::kRnePost), on);
    ApplyEffects(p, l.robot, m);
    std::string error;
    ASSERT_TRUE(l.scene->Reset("halfsit", &error));
    const auto& ft = l.robot.forces[0];
    const auto& imu = l.robot.imus[0];
    d->sensordata[ft.force_adr + 2] = kSentinel;
    d->sensordata[imu.accel_adr + 2] = kSentinel;
    d->sensordata[m->sensor_adr[0]] = kSentinel;  // q_RLEG_HIP_R: never read by sim_host
    for (int b = 0; b < m->nbody; ++b) d->cacc[6 * b + 5] = kSentinel;
    mj_step(m, d);
    EXPECT_EQ(d->sensordata[m->sensor_adr[0]], kSentinel);  // other_sensors: off
    EXPECT_EQ(d->sensordata[ft.force_adr + 2] == kSentinel, !on);
    EXPECT_EQ(d->sensordata[imu.accel_adr + 2] == kSentinel, !on);
    EXPECT_EQ(d->cacc[6 * 1 + 5] == kSentinel, !on);  // mj_rnePostConstraint did not run
    EXPECT_NE(d->sensordata[imu.gyro_adr], kSentinel);
    // the segment marks what is not measured
    shm::SensorBlock s{};
    model::FillSensors(l.robot, m, d, SelectSensors(p), &s);
    EXPECT_EQ(std::isnan(s.force[0].force[2]), !on);
    EXPECT_EQ(std::isnan(s.imu[0].accel[2]), !on);
    EXPECT_FALSE(std::isnan(s.imu[0].gyro[0]));
    EXPECT_FALSE(std::isnan(s.q[0]));
  }
  // nothing left to compute: MuJoCo's sensor stage is off altogether
  Loaded l = Load(kFlat);
  ApplyEffects(Resolve(l, "force_torque=off,gyro=off,accelerometer=off,orientation=off"), l.robot,
               l.scene->m());
  EXPECT_TRUE(l.scene->m()->opt.disableflags & mjDSBL_SENSOR);
}

//---------------- noise ----------------

TEST(EffectsNoise, OffIsExact) {
  model::InstallMujocoHandlers(nullptr);
  Loaded l = Load(kFlat);
  const EffectsPlan p = Resolve(l, "");
  ApplyEffects(p, l.robot, l.scene->m());
  std::string error;
  ASSERT_TRUE(l.scene->Reset("halfsit", &error));
  mj_step(l.scene->m(), l.scene->d());
  shm::SensorBlock s{};
  model::FillSensors(l.robot, l.scene->m(), l.scene->d(), SelectSensors(p), &s);
  const mjData* d = l.scene->d();
  EXPECT_EQ(s.q[3], d->qpos[l.robot.joints[3].qpos_adr]);
  EXPECT_EQ(s.force[0].force[2], -d->sensordata[l.robot.forces[0].force_adr + 2]);
  EXPECT_EQ(s.imu[0].gyro[1], d->sensordata[l.robot.imus[0].gyro_adr + 1]);
}

// --effects noise=on is the sensor model (robot_model/sensor_params.h) with every sensor's noise
// set from the effect's standard deviations: applied on a block as sim_host does
TEST(EffectsNoise, StandardDeviationAndSeed) {
  model::InstallMujocoHandlers(nullptr);
  Loaded l = Load(kFlat);
  EffectsPlan p = Resolve(l, "noise=on,noise.force=2.5,noise.q=0.001,noise.tau=0.3,noise.seed=42");
  EXPECT_EQ(p.noise.force, 2.5);
  EXPECT_EQ(p.noise.gyro, NoiseOptions{}.gyro);  // the documented default
  const model::SensorSelection sel = SelectSensors(p);
  auto model_of = [&](const NoiseOptions& o) { return model::SensorModel(NoiseAsSensorParams(o, l.robot), o.seed); };
  model::SensorModel noise = model_of(p.noise);
  // N samples of zero-valued fields: the sample standard deviation of a Gaussian has a
  // relative spread of 1/sqrt(2N) = 0.3 % at N = 50000; allow 2 %
  const int n = 50000;
  double sq = 0, sdq = 0, stau = 0, sf = 0, sg = 0, mean_f = 0, so = 0;
  shm::SensorBlock s{};
  for (int i = 0; i < n; ++i) {
    s = shm::SensorBlock{};
    s.imu[0].quat_WI[0] = 1;
    ApplySensorModel(l.robot, sel, &noise, &s);
    sq += s.q[5] * s.q[5];
    sdq += s.dq[2] * s.dq[2];
    stau += s.tau[7] * s.tau[7];
    sf += s.force[1].force[2] * s.force[1].force[2];
    mean_f += s.force[1].force[2];
    sg += s.imu[0].gyro[0] * s.imu[0].gyro[0];
    // orientation: the rotation vector about x is 2 qx for small angles
    so += 4 * s.imu[0].quat_WI[1] * s.imu[0].quat_WI[1];
  }
  EXPECT_NEAR(std::sqrt(sq / n), 0.001, 0.02 * 0.001);
  EXPECT_NEAR(std::sqrt(sdq / n), NoiseOptions{}.dq, 0.02 * NoiseOptions{}.dq);
  EXPECT_NEAR(std::sqrt(stau / n), 0.3, 0.02 * 0.3);
  EXPECT_NEAR(std::sqrt(sf / n), 2.5, 0.02 * 2.5);
  EXPECT_NEAR(mean_f / n, 0.0, 4 * 2.5 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sg / n), NoiseOptions{}.gyro, 0.02 * NoiseOptions{}.gyro);
  EXPECT_NEAR(std::sqrt(so / n), NoiseOptions{}.orientation, 0.02 * NoiseOptions{}.orientation);
  // the same seed gives the same noise, another seed another
  model::SensorModel a = model_of(p.noise), b = model_of(p.noise);
  NoiseOptions other = p.noise;
  other.seed = 43;
  model::SensorModel c = model_of(other);
  shm::SensorBlock sa{}, sb{}, sc{};
  ApplySensorModel(l.robot, sel, &a, &sa);
  ApplySensorModel(l.robot, sel, &b, &sb);
  ApplySensorModel(l.robot, sel, &c, &sc);
  EXPECT_EQ(sa.q[0], sb.q[0]);
  EXPECT_EQ(sa.force[0].torque[1], sb.force[0].torque[1]);
  EXPECT_NE(sa.q[0], sc.q[0]);
  // kinds that are off stay NaN
  p = Resolve(l, "noise=on,force_torque=off");
  model::SensorModel d = model_of(p.noise);
  shm::SensorBlock sd{};
  sd.force[0].force[0] = std::nan("");
  ApplySensorModel(l.robot, SelectSensors(p), &d, &sd);
  EXPECT_TRUE(std::isnan(sd.force[0].force[0]));
}

// a sensor file's noise and the effect's are independent: their standard deviations add in
// quadrature, the file's bias stays
TEST(EffectsNoise, AddsToASensorFileInQuadrature) {
  model::InstallMujocoHandlers(nullptr);
  Loaded l = Load(kFlat);
  std::vector<std::string> joints, imus, forces;
  for (const auto& j : l.robot.joints) joints.push_back(j.name);
  for (const auto& u : l.robot.imus) imus.push_back(u.name);
  for (const auto& f : l.robot.forces) forces.push_back(f.name);
  model::SensorParams file, bound;
  file.encoders.push_back({joints[3], 0.01, 0.003, ""});
  std::string error;
  ASSERT_TRUE(model::BindSensorParams(file, joints, imus, forces, &bound, &error)) << error;
  NoiseOptions o;
  o.q = 0.004;
  model::AddSensorParams(NoiseAsSensorParams(o, l.robot), &bound);
  EXPECT_DOUBLE_EQ(bound.encoders[3].noise, 0.005);  // sqrt(0.003^2 + 0.004^2)
  EXPECT_DOUBLE_EQ(bound.encoders[3].bias, 0.01);
  EXPECT_DOUBLE_EQ(bound.encoders[4].noise, 0.004);
  EXPECT_DOUBLE_EQ(bound.encoders[4].velocity_noise, o.dq);
  EXPECT_DOUBLE_EQ(bound.forces[0].noise[4], o.torque);
  EXPECT_DOUBLE_EQ(bound.imus[0].orientation_noise, o.orientation);
}

}  // namespace
}  // namespace ohrp::sim
