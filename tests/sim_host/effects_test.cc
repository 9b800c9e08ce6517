// Tests sim_host/effects.h: which effects a scene calls for (each resolution rule and
// dependency), that an effect switched off is really off in MuJoCo (gravity, limits, passive
// forces, contact, sensors, mj_rnePostConstraint), the sensor noise (standard deviation,
// seed, exact when off), and `sim_host --explain` as a process.
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/process.h"
#include "runner/scenario.h"
#include "sim_host/effects.h"
#include "sim_host/model.h"
#include "test_models.h"

namespace ohrp::sim {
namespace {

const std::string kFlat = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";

// a hinge pendulum with a motor, no sensors, no soles, a camera-less scene
constexpr const char* kPendulum = R"(
<mujoco model="pendulum">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <body name="link">
      <joint name="j" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator><motor name="j" joint="j" ctrllimited="true" ctrlrange="-10 10"/></actuator>
</mujoco>
)";

// two free boxes above a floor, and a two-link robot whose links may touch each other
constexpr const char* kBoxes = R"(
<mujoco model="boxes">
  <compiler angle="radian"/>
  <option timestep="0.002" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="box1" pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    <body name="box2" pos="1 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    <body name="arm" pos="3 0 1">
      <joint name="a1" type="hinge" axis="0 1 0"/>
      <geom type="sphere" size="0.05" pos="0.3 0 0" mass="1"/>
      <body name="forearm" pos="0.6 0 0">
        <joint name="a2" type="hinge" axis="0 1 0"/>
        <geom type="sphere" size="0.05" pos="-0.3 0 0" mass="1"/>
        <body name="hand">
          <joint name="a3" type="hinge" axis="0 1 0"/>
          <geom type="sphere" size="0.05" pos="-0.3 0 0.02" mass="1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="a1"/><motor joint="a2"/><motor joint="a3"/></actuator>
</mujoco>
)";

struct Loaded {
  std::unique_ptr<Scene> scene;
  RobotMap robot;
};

Loaded Load(const std::string& path) {
  Loaded l;
  std::string error;
  l.scene = Scene::Load(path, &error);
  EXPECT_TRUE(l.scene) << error;
  EXPECT_TRUE(MapRobot(l.scene->m(), &l.robot, &error)) << error;
  return l;
}

Loaded LoadText(const char* xml) { return Load(testing::WriteTemp(xml)); }

EffectsPlan Resolve(const Loaded& l, const std::string& spec, bool log = false,
                    ContactModel contact = ContactModel::kAuto) {
  EffectRequests req;
  std::string error;
  EXPECT_TRUE(ParseEffectRequests(spec, &req, &error)) << error;
  FeetOptions feet;
  feet.model = contact;
  EffectsPlan plan;
  EXPECT_TRUE(ResolveEffects(l.scene->m(), l.robot, feet, log, req, &plan, &error)) << error;
  return plan;
}

// the error of a resolution that must fail
std::string Refused(const Loaded& l, const std::string& spec, bool log = false) {
  EffectRequests req;
  std::string error;
  if (!ParseEffectRequests(spec, &req, &error)) return error;
  EffectsPlan plan;
  EXPECT_FALSE(ResolveEffects(l.scene->m(), l.robot, FeetOptions{}, log, req, &plan, &error))
      << spec << " was accepted";
  return error;
}

// applies the plan to the model and resets it (Reset runs mj_forward)
void Apply(const Loaded& l, const EffectsPlan& p) {
  ApplyEffects(p, l.robot, l.scene->m());
  std::string error;
  ASSERT_TRUE(l.scene->Reset("", &error)) << error;
}

class EffectsFlat : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    InstallMujocoHandlers(nullptr);
    flat_ = new Loaded(Load(kFlat));
  }
  static void TearDownTestSuite() { delete flat_; }
  static Loaded* flat_;
};
Loaded* EffectsFlat::flat_ = nullptr;

//---------------- resolution ----------------

TEST_F(EffectsFlat, DefaultsOfTheStandingScene) {
  const EffectsPlan p = Resolve(*flat_, "");
  EXPECT_TRUE(p.on(Effect::kGravity));
  EXPECT_TRUE(p.on(Effect::kJointLimits));
  EXPECT_TRUE(p.on(Effect::kPassive));  // damping 0.1 on every joint
  EXPECT_TRUE(p.on(Effect::kSoftContact));
  EXPECT_FALSE(p.on(Effect::kNativeContact)) << p[Effect::kNativeContact].reason;
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_FALSE(p.on(Effect::kSelfCollision));  // declared (the robot has geometry), not asked for
  EXPECT_TRUE(p[Effect::kSelfCollision].declared);
  EXPECT_NE(p[Effect::kSelfCollision].reason.find("30 links have 406 non-adjacent pairs"), std::string::npos)
      << p[Effect::kSelfCollision].reason;
  EXPECT_TRUE(p.on(Effect::kForceTorque));
  EXPECT_TRUE(p.on(Effect::kAccelerometer));
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_EQ(p[Effect::kRnePost].reason, "needed by force_torque, accelerometer");
  EXPECT_FALSE(p.on(Effect::kOtherSensors));
  EXPECT_NE(p[Effect::kOtherSensors].reason.find("87 MuJoCo sensors"), std::string::npos);
  EXPECT_FALSE(p.on(Effect::kNoise));
  // on, but rendered only while a program asks (sim_host/cameras.h)
  EXPECT_TRUE(p.on(Effect::kCameras));
  EXPECT_NE(p[Effect::kCameras].reason.find("rendered only while an attached program asks"),
            std::string::npos);
  EXPECT_FALSE(p.on(Effect::kLog));
  EXPECT_FALSE(p.on(Effect::kLogForceTorque));
  // the soles' pairs with the floor exist, handed to the soft-foot contact; the ankles are
  // excluded from each other by the model
  ASSERT_EQ(p.pairs.size(), 2u);
  for (const auto& cp : p.pairs) {
    EXPECT_FALSE(cp.on);
    EXPECT_TRUE(cp.soles);
  }
}

TEST_F(EffectsFlat, NativeContactTakesTheSolePairs) {
  const EffectsPlan p = Resolve(*flat_, "", false, ContactModel::kNative);
  EXPECT_FALSE(p.on(Effect::kSoftContact));
  EXPECT_TRUE(p.on(Effect::kNativeContact));
  for (const auto& cp : p.pairs) EXPECT_TRUE(cp.on) << cp.name;
}

TEST_F(EffectsFlat, RnePostIsNeededByForceTorqueAndAccelerometer) {
  EffectsPlan p = Resolve(*flat_, "accelerometer=off");
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_EQ(p[Effect::kRnePost].reason, "needed by force_torque");
  p = Resolve(*flat_, "accelerometer=off,force_torque=off");
  EXPECT_FALSE(p.on(Effect::kRnePost));
  // switching the shared need off takes both (they were on by default)
  p = Resolve(*flat_, "rne_post=off");
  EXPECT_FALSE(p.on(Effect::kForceTorque));
  EXPECT_FALSE(p.on(Effect::kAccelerometer));
  EXPECT_EQ(p[Effect::kForceTorque].reason, "needs rne_post, which is off");
  EXPECT_TRUE(p.on(Effect::kGyro));  // a velocity-stage sensor: no need of it
  // asking for both is a conflict
  EXPECT_NE(Refused(*flat_, "rne_post=off,force_torque=on").find("force_torque=on needs rne_post"),
            std::string::npos);
}

TEST_F(EffectsFlat, LogChannelsNeedTheirSensors) {
  EffectsPlan p = Resolve(*flat_, "", true);
  EXPECT_TRUE(p.on(Effect::kLog));
  EXPECT_TRUE(p.on(Effect::kLogForceTorque));
  EXPECT_TRUE(p.on(Effect::kLogImu));
  p = Resolve(*flat_, "force_torque=off", true);
  EXPECT_FALSE(p.on(Effect::kLogForceTorque));
  EXPECT_EQ(p[Effect::kLogForceTorque].reason, "needs force_torque, which is off");
  EXPECT_TRUE(p.on(Effect::kRnePost));  // the accelerometer still needs it
  // a requested channel switches its sensor back on, and its sensor's needs
  p = Resolve(*flat_, "log_force_torque=on,accelerometer=off", true);
  EXPECT_TRUE(p.on(Effect::kForceTorque));
  EXPECT_TRUE(p.on(Effect::kRnePost));
  EXPECT_NE(Refused(*flat_, "log_force_torque=on,force_torque=off", true).find("needs force_torque"),
            std::string::npos);
  EXPECT_NE(Refused(*flat_, "log_imu=on").find("log_imu=on"), std::string::npos);  // no --log
  p = Resolve(*flat_, "log=off", true);
  EXPECT_FALSE(p.on(Effect::kLogJoints));
}

TEST_F(EffectsFlat, SelfCollisionIsOnWhenAsked) {
  const EffectsPlan p = Resolve(*flat_, "self_collision=on");
  EXPECT_TRUE(p.on(Effect::kSelfCollision));
  EXPECT_EQ(p[Effect::kSelfCollision].reason, "switched on by request");
  // no physics changes with it: MuJoCo's contact stays off, the pairs as without it
  EXPECT_FALSE(p.on(Effect::kNativeContact));
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_EQ(p.pairs.size(), Resolve(*flat_, "").pairs.size());
}

TEST_F(EffectsFlat, WhatCannotBeSwitchedOnIsRefused) {
  EXPECT_NE(Refused(LoadText(kPendulum), "cameras=on").find("the scene declares no camera"),
            std::string::npos);
  EXPECT_FALSE(Resolve(*flat_, "cameras=off").on(Effect::kCameras));
  EXPECT_NE(Refused(*flat_, "soft_contact=off").find("--contact"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "self_contact=on").find("cannot be switched on"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "native_contact=on").find("cannot be switched on"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "contact:WAIST/world=off").find("no such colliding body pair"),
            std::string::npos);
  EXPECT_NE(Refused(*flat_, "grav=off").find("unknown effect 'grav'"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "gravity=maybe").find("on or off"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "noise.force=-1").find("standard deviation"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "noise.color=1").find("unknown noise kind"), std::string::npos);
  EXPECT_NE(Refused(*flat_, "contact:LLEG_ANKLE_R=off").find("two bodies"), std::string::npos);
}

TEST(Effects, ModelWithoutSolesOrSensors) {
  InstallMujocoHandlers(nullptr);
  const Loaded l = LoadText(kPendulum);
  const EffectsPlan p = Resolve(l, "");
  EXPECT_TRUE(p.on(Effect::kGravity));
  EXPECT_FALSE(p.on(Effect::kJointLimits));
  EXPECT_EQ(p[Effect::kJointLimits].reason, "no limited joint or tendon in the scene");
  EXPECT_FALSE(p.on(Effect::kPassive));
  EXPECT_FALSE(p.on(Effect::kSoftContact));
  EXPECT_EQ(p[Effect::kSoftContact].reason, "--contact native (the model has no *_SOLE geoms)");
  EXPECT_FALSE(p.on(Effect::kNativeContact));
  EXPECT_FALSE(p.on(Effect::kForceTorque));
  EXPECT_FALSE(p.on(Effect::kGyro));
  EXPECT_FALSE(p.on(Effect::kRnePost));
  EXPECT_TRUE(p.on(Effect::kEncoders));
  EXPECT_EQ(p[Effect::kCameras].reason, "the scene declares no camera");
  const std::string table = p.Table();
  EXPECT_NE(table.find("force_torque       off    the scene declares no F/T sensor"), std::string::npos)
      << table;
  EXPECT_EQ(table.find("contact pairs"), std::string::npos);  // none
  EXPECT_NE(Refused(l, "force_torque=on").find("the scene declares no F/T sensor"), std::string::npos);
  // one link: nothing for the self-collision check
  EXPECT_NE(Refused(l, "self_collision=on").find("no two non-adjacent links"), std::string::npos);
}

TEST(Effects, SelfContactNeedsNativeContact) {
  InstallMujocoHandlers(nullptr);
  // the hand's sphere overlaps the arm's (its grandparent: not filtered as parent-child); the
  // forearm's overlaps both but is the child of one and the parent of the other (filtered)
  Loaded l = LoadText(kBoxes);
  EffectsPlan p = Resolve(l, "");
  EXPECT_TRUE(p.on(Effect::kNativeContact));
  EXPECT_TRUE(p.on(Effect::kSelfContact)) << p[Effect::kSelfContact].reason;
  std::vector<std::string> self;
  for (const auto& cp : p.pairs)
    if (cp.self) self.push_back(cp.name);
  EXPECT_EQ(self, std::vector<std::string>{"arm/hand"});
  // contacts between two bodies after Reset's mj_forward
  auto contacts = [](const Loaded& x, const char* b1, const char* b2) {
    const mjModel* m = x.scene->m();
    const int i1 = mj_name2id(m, mjOBJ_BODY, b1), i2 = mj_name2id(m, mjOBJ_BODY, b2);
    int n = 0;
    for (int c = 0; c < x.scene->d()->ncon; ++c) {
      const int g1 = m->geom_bodyid[x.scene->d()->contact[c].geom1];
      const int g2 = m->geom_bodyid[x.scene->d()->contact[c].geom2];
      n += (g1 == i1 && g2 == i2) || (g1 == i2 && g2 == i1);
    }
    return n;
  };
  Apply(l, p);
  EXPECT_EQ(contacts(l, "arm", "hand"), 1);
  p = Resolve(l, "native_contact=off");
  EXPECT_FALSE(p.on(Effect::kSelfContact));
  EXPECT_EQ(p[Effect::kSelfContact].reason, "needs native_contact, which is off");
  for (const auto& cp : p.pairs) EXPECT_FALSE(cp.on);
  // switched off: the contact filter drops the pair
  Loaded l2 = LoadText(kBoxes);
  p = Resolve(l2, "self_contact=off");
  for (const auto& cp : p.pairs) EXPECT_EQ(cp.on, !cp.self) << cp.name << ": " << cp.reason;
  Apply(l2, p);
  EXPECT_EQ(contacts(l2, "arm", "hand"), 0);
  EXPECT_EQ(contacts(l2, "box1", "world"), 4);  // the other pairs are untouched
  ClearContactFilter();
  p = Resolve(l2, "contact:box1/world=off");
  for (const auto& cp : p.pairs)
    EXPECT_EQ(cp.on, cp.name != "world/box1") << cp.name << ": " << cp.reason;
}

//---------------- switched off is really off ----------------

TEST(EffectsOff, GravityOffAFreeBodyDoesNotFall) {
  InstallMujocoHandlers(nullptr);
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
  InstallMujocoHandlers(nullptr);
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
  InstallMujocoHandlers(nullptr);
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
  InstallMujocoHandlers(nullptr);
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
  InstallMujocoHandlers(nullptr);
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
    FillSensors(l.robot, m, d, SelectSensors(p), &s);
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
  InstallMujocoHandlers(nullptr);
  Loaded l = Load(kFlat);
  const EffectsPlan p = Resolve(l, "");
  ApplyEffects(p, l.robot, l.scene->m());
  std::string error;
  ASSERT_TRUE(l.scene->Reset("halfsit", &error));
  mj_step(l.scene->m(), l.scene->d());
  shm::SensorBlock s{};
  FillSensors(l.robot, l.scene->m(), l.scene->d(), SelectSensors(p), &s);
  const mjData* d = l.scene->d();
  EXPECT_EQ(s.q[3], d->qpos[l.robot.joints[3].qpos_adr]);
  EXPECT_EQ(s.force[0].force[2], -d->sensordata[l.robot.forces[0].force_adr + 2]);
  EXPECT_EQ(s.imu[0].gyro[1], d->sensordata[l.robot.imus[0].gyro_adr + 1]);
}

TEST(EffectsNoise, StandardDeviationAndSeed) {
  InstallMujocoHandlers(nullptr);
  Loaded l = Load(kFlat);
  EffectsPlan p = Resolve(l, "noise=on,noise.force=2.5,noise.q=0.001,noise.seed=42");
  EXPECT_EQ(p.noise.force, 2.5);
  EXPECT_EQ(p.noise.gyro, NoiseOptions{}.gyro);  // the documented default
  const SensorSelection sel = SelectSensors(p);
  SensorNoise noise(p.noise, sel);
  // N samples of zero-valued fields: the sample standard deviation of a Gaussian has a
  // relative spread of 1/sqrt(2N) = 0.3 % at N = 50000; allow 2 %
  const int n = 50000;
  double sq = 0, sf = 0, sg = 0, mean_f = 0, so = 0;
  shm::SensorBlock s{};
  for (int i = 0; i < n; ++i) {
    s = shm::SensorBlock{};
    s.imu[0].quat_WI[0] = 1;
    noise.Apply(l.robot, &s);
    sq += s.q[5] * s.q[5];
    sf += s.force[1].force[2] * s.force[1].force[2];
    mean_f += s.force[1].force[2];
    sg += s.imu[0].gyro[0] * s.imu[0].gyro[0];
    // orientation: the rotation vector about x is 2 qx for small angles
    so += 4 * s.imu[0].quat_WI[1] * s.imu[0].quat_WI[1];
  }
  EXPECT_NEAR(std::sqrt(sq / n), 0.001, 0.02 * 0.001);
  EXPECT_NEAR(std::sqrt(sf / n), 2.5, 0.02 * 2.5);
  EXPECT_NEAR(mean_f / n, 0.0, 4 * 2.5 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sg / n), NoiseOptions{}.gyro, 0.02 * NoiseOptions{}.gyro);
  EXPECT_NEAR(std::sqrt(so / n), NoiseOptions{}.orientation, 0.02 * NoiseOptions{}.orientation);
  // the same seed gives the same noise, another seed another
  SensorNoise a(p.noise, sel), b(p.noise, sel);
  NoiseOptions other = p.noise;
  other.seed = 43;
  SensorNoise c(other, sel);
  shm::SensorBlock sa{}, sb{}, sc{};
  a.Apply(l.robot, &sa);
  b.Apply(l.robot, &sb);
  c.Apply(l.robot, &sc);
  EXPECT_EQ(sa.q[0], sb.q[0]);
  EXPECT_EQ(sa.force[0].torque[1], sb.force[0].torque[1]);
  EXPECT_NE(sa.q[0], sc.q[0]);
  // kinds that are off stay NaN
  p = Resolve(l, "noise=on,force_torque=off");
  SensorNoise d(p.noise, SelectSensors(p));
  shm::SensorBlock sd{};
  sd.force[0].force[0] = std::nan("");
  d.Apply(l.robot, &sd);
  EXPECT_TRUE(std::isnan(sd.force[0].force[0]));
}

//---------------- sim_host --explain, as a process ----------------

// runs sim_host with `args`; returns its exit code, stdout and stderr in *out, *err
int RunSimHost(const std::vector<std::string>& args, std::string* out, std::string* err) {
  const std::string o = testing::WriteTemp("", ".out"), e = testing::WriteTemp("", ".err");
  std::vector<std::string> argv = {std::string(OHRP_BIN_DIR) + "/sim_host"};
  argv.insert(argv.end(), args.begin(), args.end());
  const int code = ohrp::testing::WaitExit(ohrp::testing::Spawn(argv, {.out = o, .err = e}),
                                           ohrp::testing::kNoTimeout);
  std::ifstream fo(o), fe(e);
  std::stringstream so, se;
  so << fo.rdbuf();
  se << fe.rdbuf();
  *out = so.str();
  *err = se.str();
  std::filesystem::remove(o);
  std::filesystem::remove(e);
  return code;
}

TEST(EffectsProcess, ExplainPrintsTheTableAndCreatesNoSegment) {
  const std::string segment = "effects_explain_" + std::to_string(getpid());
  std::string out, err;
  ASSERT_EQ(RunSimHost({"--scene", kFlat, "--keyframe", "halfsit", "--segment", segment,
                        "--explain"}, &out, &err), 0) << err;
  EXPECT_NE(out.find("rne_post           on     needed by force_torque, accelerometer"), std::string::npos) << out;
  EXPECT_NE(out.find("soft_contact       on"), std::string::npos);
  EXPECT_NE(out.find("cameras            on     declared by the scene (LeftCamera, RightCamera): rendered only while"), std::string::npos) << out;
  EXPECT_NE(out.find("cameras: 2 (LeftCamera first), 640x480 RGB + depth, 30 frames per simulated second, rendered only while an attached program asks for them"), std::string::npos) << out;
  EXPECT_NE(out.find("world/RLEG_ANKLE_R"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists("/dev/shm/ohrp_" + segment));
  EXPECT_TRUE(err.empty()) << err;
  // bad requests: exit 2 with the reason
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--effects", "self_contact=on"}, &out, &err), 2);
  EXPECT_NE(err.find("cannot be switched on"), std::string::npos) << err;
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--camera-size", "641x480"}, &out, &err), 2);
  EXPECT_NE(err.find("--camera-size: camera size '641x480' must be WIDTHxHEIGHT within 1x1 to 640x480"), std::string::npos) << err;
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--effects", "gravity"}, &out, &err), 2);
  EXPECT_NE(err.find("NAME=VALUE"), std::string::npos) << err;
}

TEST(EffectsProcess, ARunPrintsTheShortTableAndSummarisesIt) {
  const std::string dir = testing::WriteTemp("", ".d");
  std::filesystem::remove(dir);
  std::filesystem::create_directory(dir);
  const std::string segment = "effects_run_" + std::to_string(getpid());
  std::string out, err;
  ASSERT_EQ(RunSimHost({"--scene", kFlat, "--keyframe", "halfsit", "--segment", segment,
                        "--wait-controller", "0", "--duration", "0.05", "--progress", "0",
                        "--log", dir + "/log.csv", "--summary", dir + "/sum.json",
                        "--effects", "log_force_torque=off,noise=on"}, &out, &err), 0) << err;
  EXPECT_NE(err.find("sim_host: effects on: gravity"), std::string::npos) << err;
  EXPECT_NE(err.find("sim_host: effects off: native_contact"), std::string::npos) << err;
  std::ifstream sum(dir + "/sum.json");
  std::stringstream ss;
  ss << sum.rdbuf();
  EXPECT_NE(ss.str().find("\"effects\""), std::string::npos);
  EXPECT_NE(ss.str().find("needed by force_torque, accelerometer"), std::string::npos);
  // the log has no F/T columns, the IMU's are there
  std::ifstream log(dir + "/log.csv");
  std::string header;
  std::getline(log, header);
  EXPECT_EQ(header.find("rfsensor_fx"), std::string::npos) << header;
  EXPECT_NE(header.find("imu_gx"), std::string::npos) << header;
  std::filesystem::remove_all(dir);
}

//---------------- the scenario key ----------------

TEST(EffectsScenario, TheKeyBecomesSimHostsEffectsOption) {
  const std::string path = testing::WriteTemp(
      "scene: mjcf/hrp1s/scene_flat.xml\nduration: 1\n"
      "effects:\n  gravity: off\n  noise: on\n  noise.force: 2.5\n"
      "controllers: []\nchecks: [{type: not_fallen}]\n", ".yaml");
  runner::Scenario s;
  std::string error;
  ASSERT_TRUE(runner::LoadScenario(path, &s, &error)) << error;
  EXPECT_EQ(s.effects.at("noise"), "on");
  ASSERT_GE(s.sim_args.size(), 2u);
  EXPECT_EQ(s.sim_args[0], "--effects");
  EXPECT_EQ(s.sim_args[1], "gravity=off,noise=on,noise.force=2.5");
  // and sim_host reads what the scenario wrote
  EffectRequests req;
  ASSERT_TRUE(ParseEffectRequests(s.sim_args[1], &req, &error)) << error;
  EXPECT_EQ(req.request[static_cast<int>(Effect::kGravity)], 0);
  EXPECT_EQ(req.noise.force, 2.5);
  const std::string bad = testing::WriteTemp(
      "scene: mjcf/hrp1s/scene_flat.xml\neffects: [gravity]\n", ".yaml");
  EXPECT_FALSE(runner::LoadScenario(bad, &s, &error));
  EXPECT_NE(error.find("'effects' must be a mapping"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::sim
