// Tests the actuator laws (actuator.h): for every MuJoCo actuator type that drives one joint,
// the control ControlFor computes makes MuJoCo apply exactly the commanded joint torque; ranges
// clamp and say so; actuators that cannot be inverted are refused with a reason; the robot map
// takes geared motors and lists passive joints; the servo's torque reaches a geared joint.
#include "robot_model/actuator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>

#include "robot_model/model.h"
#include "robot_model/servo.h"

namespace ohrp::model {
namespace {

// one hinge (no gravity, no damping) driven by the actuator element `actuator`
std::string OneJoint(const std::string& actuator) {
  return R"(<mujoco model="one"><compiler autolimits="true" angle="radian"/><option gravity="0 0 0"/><worldbody><body name="link">
    <joint name="j" type="hinge" axis="0 1 0" range="-2 2" limited="true"/>
    <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.03" mass="1"/></body></worldbody>
    <actuator>)" + actuator + "</actuator></mujoco>";
}

struct Loaded {
  mjModel* m = nullptr;
  mjData* d = nullptr;
  ~Loaded() {
    if (d) mj_deleteData(d);
    if (m) mj_deleteModel(m);
  }
};

std::unique_ptr<Loaded> Load(const std::string& xml) {
  char error[1000] = "";
  auto vfs = std::make_unique<mjVFS>();  // large: not on the stack
  mj_defaultVFS(vfs.get());
  mj_makeEmptyFileVFS(vfs.get(), "model.xml", static_cast<int>(xml.size()));
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml.data(), xml.size());
  auto l = std::make_unique<Loaded>();
  l->m = mj_loadXML("model.xml", vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  EXPECT_NE(l->m, nullptr) << error;
  if (l->m) l->d = mj_makeData(l->m);
  return l;
}

// the joint torque MuJoCo applies for `ctrl` at (q, dq)
double MujocoTorque(Loaded* l, double ctrl, double q, double dq) {
  l->d->qpos[0] = q;
  l->d->qvel[0] = dq;
  l->d->ctrl[0] = ctrl;
  mj_forward(l->m, l->d);
  return l->d->qfrc_actuator[0];
}

struct Case {
  const char* name;
  const char* actuator;
  ActuatorKind kind;
};

class ActuatorTypes : public ::testing::TestWithParam<Case> {};

TEST_P(ActuatorTypes, ControlGivesTheCommandedJointTorque) {
  auto l = Load(OneJoint(GetParam().actuator));
  ASSERT_TRUE(l->m);
  ActuatorLaw law;
  std::string error;
  ASSERT_TRUE(ReadActuatorLaw(l->m, 0, &law, &error)) << error;
  EXPECT_EQ(law.kind, GetParam().kind);
  for (double tau : {-7.0, 0.0, 3.5}) {
    for (double q : {-0.4, 0.0, 0.9}) {
      for (double dq : {-1.5, 0.0, 2.0}) {
        bool clamped = true;
        const double ctrl = law.ControlFor(tau, q, dq, &clamped);
        EXPECT_FALSE(clamped);
        EXPECT_NEAR(MujocoTorque(l.get(), ctrl, q, dq), tau, 1e-9)
            << law.Describe() << " at q=" << q << " dq=" << dq;
        EXPECT_NEAR(law.TorqueFor(ctrl, q, dq), tau, 1e-9);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(
    Mujoco222, ActuatorTypes,
    ::testing::Values(
        Case{"motor", R"(<motor joint="j"/>)", ActuatorKind::kMotor},
        Case{"geared_motor", R"(<motor joint="j" gear="25"/>)", ActuatorKind::kMotor},
        Case{"negative_gear", R"(<motor joint="j" gear="-3"/>)", ActuatorKind::kMotor},
        Case{"position", R"(<position joint="j" kp="80"/>)", ActuatorKind::kPosition},
        Case{"geared_position", R"(<position joint="j" kp="80" gear="4"/>)", ActuatorKind::kPosition},
        Case{"velocity", R"(<velocity joint="j" kv="6" gear="2"/>)", ActuatorKind::kVelocity},
        Case{"general", R"(<general joint="j" gainprm="3" biastype="affine" biasprm="0.5 -2 -0.7" gear="1.5"/>)",
             ActuatorKind::kGeneral}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(ActuatorLaw, CtrlRangeClampsAndSaysSo) {
  auto l = Load(OneJoint(R"(<motor joint="j" gear="25" ctrlrange="-4.5 4.5"/>)"));
  ActuatorLaw law;
  std::string error;
  ASSERT_TRUE(ReadActuatorLaw(l->m, 0, &law, &error)) << error;
  EXPECT_DOUBLE_EQ(law.TorqueLimit(1e9), 112.5);
  bool clamped = false;
  EXPECT_DOUBLE_EQ(law.ControlFor(112.5, 0, 0, &clamped), 4.5);
  EXPECT_FALSE(clamped);  // at the limit, not beyond
  EXPECT_DOUBLE_EQ(law.ControlFor(200.0, 0, 0, &clamped), 4.5);
  EXPECT_TRUE(clamped);
}

TEST(ActuatorLaw, ForceRangeOfAPositionServoClamps) {
  auto l = Load(OneJoint(R"(<position joint="j" kp="100" forcerange="-10 10"/>)"));
  ActuatorLaw law;
  std::string error;
  ASSERT_TRUE(ReadActuatorLaw(l->m, 0, &law, &error)) << error;
  EXPECT_DOUBLE_EQ(law.TorqueLimit(1e9), 10.0);
  bool clamped = false;
  const double ctrl = law.ControlFor(25.0, 0.2, 0.0, &clamped);
  EXPECT_TRUE(clamped);
  EXPECT_NEAR(MujocoTorque(l.get(), ctrl, 0.2, 0.0), 10.0, 1e-9);
}

TEST(ActuatorLaw, StateDependentLawWithoutForceRangeHasNoTorqueLimit) {
  auto l = Load(OneJoint(R"(<position joint="j" kp="100" ctrlrange="-1 1"/>)"));
  ActuatorLaw law;
  std::string error;
  ASSERT_TRUE(ReadActuatorLaw(l->m, 0, &law, &error)) << error;
  EXPECT_DOUBLE_EQ(law.TorqueLimit(1e9), 1e9);
  EXPECT_NE(law.Describe().find("position kp=100"), std::string::npos) << law.Describe();
  EXPECT_NE(law.Describe().find("ctrl in [-1, 1]"), std::string::npos) << law.Describe();
}

TEST(ActuatorLaw, RefusesActivationDynamicsWithAReason) {
  auto l = Load(OneJoint(R"(<general name="filtered" joint="j" dyntype="filter" dynprm="0.05"/>)"));
  ActuatorLaw law;
  std::string error;
  EXPECT_FALSE(ReadActuatorLaw(l->m, 0, &law, &error));
  EXPECT_NE(error.find("actuator 'filtered'"), std::string::npos) << error;
  EXPECT_NE(error.find("activation dynamics"), std::string::npos) << error;
}

TEST(ActuatorLaw, RefusesAZeroGain) {
  auto l = Load(OneJoint(R"(<general name="dead" joint="j" gainprm="0"/>)"));
  ActuatorLaw law;
  std::string error;
  EXPECT_FALSE(ReadActuatorLaw(l->m, 0, &law, &error));
  EXPECT_NE(error.find("non-zero"), std::string::npos) << error;
}

//---------------- the robot map and the servo on these actuators ----------------

// a floating two-link leg: a geared knee motor, a passive spring "shin" joint, and a free box
constexpr char kLeg[] = R"(<mujoco model="leg"><compiler autolimits="true"/><worldbody>
  <body name="pelvis" pos="0 0 1"><freejoint/><geom type="sphere" size="0.1" mass="5"/>
    <body name="thigh"><joint name="knee" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.03" mass="1"/>
      <body name="shin" pos="0 0 -0.4"><joint name="shin" axis="0 1 0" stiffness="100"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.4" size="0.03" mass="1"/></body></body></body>
  <body name="box" pos="2 0 0.2"><freejoint/><geom type="sphere" size="0.05" mass="1"/><body><joint name="lid" axis="1 0 0"/>
    <geom type="box" size="0.1 0.1 0.1" mass="3"/></body></body>
  </worldbody><actuator><motor joint="knee" gear="16" ctrlrange="-12.2 12.2"/></actuator></mujoco>)";

TEST(RobotMap, TakesAGearedMotorAndListsPassiveJointsOfTheRobotOnly) {
  auto l = Load(kLeg);
  RobotMap robot;
  std::string error;
  ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
  ASSERT_EQ(robot.joints.size(), 1u);
  EXPECT_EQ(robot.joints[0].name, "knee");
  EXPECT_NEAR(robot.joints[0].tau_max, 16 * 12.2, 1e-9);
  ASSERT_EQ(robot.passive.size(), 1u);  // the box's lid is not the robot's
  EXPECT_EQ(robot.passive[0].name, "shin");
  EXPECT_NEAR(robot.total_mass, 7.0, 1e-9);  // the box is not the robot's either
}

// a sensor of a pair without its partner is not published, and says so (issue 31: a lone
// <force> or <gyro> used to vanish without a word); complete pairs are published
TEST(RobotMap, ALoneForceOrGyroIsNamedAsNotPublished) {
  const std::string xml = R"(<mujoco model="s"><worldbody><body name="link">
    <joint name="j" type="hinge" axis="0 1 0"/><geom type="sphere" size="0.05" mass="1"/>
    <site name="ankle"/><site name="chest"/><site name="hip"/></body></worldbody>
    <actuator><motor joint="j"/></actuator>
    <sensor><force name="f_only" site="ankle"/><gyro site="chest"/>
            <force site="hip"/><torque site="hip"/></sensor></mujoco>)";
  auto l = Load(xml);
  RobotMap robot;
  std::string error;
  ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
  EXPECT_EQ(robot.forces.size(), 1u);  // the pair on the hip
  EXPECT_TRUE(robot.imus.empty());
  ASSERT_EQ(robot.unpublished.size(), 2u);
  EXPECT_NE(robot.unpublished[0].find("<force> sensor 'f_only' on site 'ankle' has no <torque>"),
            std::string::npos) << robot.unpublished[0];
  EXPECT_NE(robot.unpublished[1].find("<gyro> sensor on site 'chest' has no <accelerometer>"),
            std::string::npos) << robot.unpublished[1];
}

// more force/torque sensors or IMUs than the segment carries: the robot is not refused; the
// first ones in the model's order are published and the others named
TEST(RobotMap, SensorsBeyondTheSegmentsRoomAreNamedNotRefused) {
  std::string sites, sensors;
  for (int i = 0; i < shm::kMaxForceSensors + 1; ++i) {
    sites += "<site name=\"ft" + std::to_string(i) + "\"/>";
    sensors += "<force site=\"ft" + std::to_string(i) + "\"/><torque site=\"ft" + std::to_string(i) + "\"/>";
  }
  for (int i = 0; i < shm::kMaxImus + 1; ++i) {
    sites += "<site name=\"imu" + std::to_string(i) + "\"/>";
    sensors += "<gyro site=\"imu" + std::to_string(i) + "\"/><accelerometer site=\"imu" + std::to_string(i) + "\"/>";
  }
  auto l = Load(R"(<mujoco model="s"><worldbody><body name="link"><joint name="j" type="hinge"/>
    <geom type="sphere" size="0.05" mass="1"/>)" + sites + R"(</body></worldbody>
    <actuator><motor joint="j"/></actuator><sensor>)" + sensors + "</sensor></mujoco>");
  RobotMap robot;
  std::string error;
  ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
  ASSERT_EQ(robot.forces.size(), static_cast<size_t>(shm::kMaxForceSensors));
  ASSERT_EQ(robot.imus.size(), static_cast<size_t>(shm::kMaxImus));
  EXPECT_EQ(robot.forces.back().name, "ft" + std::to_string(shm::kMaxForceSensors - 1));
  ASSERT_EQ(robot.unpublished.size(), 2u);
  EXPECT_NE(robot.unpublished[0].find("site 'ft" + std::to_string(shm::kMaxForceSensors) + "': not published"),
            std::string::npos) << robot.unpublished[0];
  EXPECT_NE(robot.unpublished[1].find("IMU on site 'imu" + std::to_string(shm::kMaxImus) + "'"),
            std::string::npos) << robot.unpublished[1];
}

TEST(RobotMap, RefusesTwoActuatorsOnOneJoint) {
  auto l = Load(OneJoint(R"(<motor name="a" joint="j"/><position name="b" joint="j" kp="5"/>)"));
  RobotMap robot;
  std::string error;
  EXPECT_FALSE(MapRobot(l->m, &robot, &error));
  EXPECT_NE(error.find("one actuator per joint"), std::string::npos) << error;
}

// The suggested gains (the segment's default_kp/kd): a position servo the author built into
// the actuator is the servo the robot was tuned with (G1's kp 500 stands it; 6 Hz on its ankle's
// own inertia gave 18 N m/rad and it fell); a <motor> closes at 6 Hz on the joint's inertia.
// Outside MuJoCo's implicit integrator the damping is at most 0.25 I / dt (one joint: its
// effective inertia is its own, I; sim_host's servo applies it explicitly each step).
TEST(RobotMap, SuggestedGainsAreTheAuthorsPositionServoElseSixHertzOnTheInertia) {
  struct Expect {
    const char* actuator;
    double kp, kd;  // < 0: from the joint's inertia (below)
  };
  const Expect cases[] = {
      {R"(<general joint="j" gaintype="fixed" biastype="affine" gainprm="500" biasprm="0 -500 -40"/>)", 500, 40},
      {R"(<position joint="j" kp="300" gear="2"/>)", 1200, -1},  // kd: critical on the inertia
      {R"(<motor joint="j" gear="25"/>)", -1, -1},
      {R"(<velocity joint="j" kv="7"/>)", -1, -1},  // no stiffness of its own: not a position servo
  };
  for (const Expect& e : cases) {
    auto l = Load(OneJoint(e.actuator));
    RobotMap robot;
    std::string error;
    ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
    const double inertia = l->m->dof_M0[0];
    const double w = 2 * M_PI * 6.0;
    const double kp = e.kp > 0 ? e.kp : inertia * w * w;
    const double kd =
        std::min(e.kd > 0 ? e.kd : (e.kp > 0 ? 2 * std::sqrt(kp * inertia) : 2 * inertia * w),
                 0.25 * inertia / l->m->opt.timestep);
    EXPECT_NEAR(robot.joints[0].default_kp, kp, 1e-9 * kp) << e.actuator;
    EXPECT_NEAR(robot.joints[0].default_kd, kd, 1e-9 * kd) << e.actuator;
  }
}

TEST(Servo, PdTorqueReachesAGearedJointAndAPositionActuatorAlike) {
  for (const char* actuator : {R"(<motor joint="j" gear="25"/>)", R"(<position joint="j" kp="300"/>)"}) {
    auto l = Load(OneJoint(actuator));
    RobotMap robot;
    std::string error;
    ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
    Servo servo(robot);
    l->d->qpos[0] = 0.1;
    l->d->qvel[0] = -0.5;
    servo.HoldCurrent(l->d);
    shm::CommandBlock c{};
    c.njoint = 1;
    c.joint[0] = {shm::JointMode::kPosition, 0, 0.6, 0.0, 1.5, 40.0, 3.0};
    ASSERT_EQ(servo.Accept(c), 0) << actuator;
    servo.Apply(l->m, l->d);
    mj_forward(l->m, l->d);
    const double expected = 40.0 * (0.6 - 0.1) + 3.0 * (0.0 + 0.5) + 1.5;
    EXPECT_NEAR(l->d->qfrc_actuator[0], expected, 1e-9) << actuator;
    EXPECT_EQ(servo.clamped_total(), 0u);
  }
}


// A leg joint of a free robot carries the body above it: a <motor>'s suggested stiffness is at
// least 2 x the gravity stiffness of its share of that load, m_c g h_c / 2 (two legs), about a
// horizontal axis only. Closed form: a 10 kg base 0.3 m above a hip (yaw, then pitch) with a
// 0.5 m leg ending in a 0.01 kg foot: the pitch hinge's own inertia gives 6 Hz ~ 0.0025 x
// 37.7^2 = 3.6 N m/rad; the floor m_c g h_c = 10.001 x 9.81 x 0.3 = 29.4 N m/rad (m_c the base
// and the hip link). The yaw hinge carries no gravity stiffness: the 6 Hz rule.
TEST(RobotMap, SuggestedStiffnessOfAMotorLegJointCarriesTheLoadAboveIt) {
  const std::string xml =
      R"(<mujoco model="a_model_whose_name_is_longer_than_the_header_has_room_for">
    <compiler autolimits="true" angle="radian"/><option timestep="0.001"/><worldbody>
    <body name="base" pos="0 0 1"><freejoint/><geom type="sphere" size="0.05" mass="10"/>
      <body name="hip" pos="0 0 -0.3"><joint name="yaw" axis="0 0 1" range="-1 1"/>
        <geom type="sphere" size="0.001" mass="0.001"/>
        <body name="leg"><joint name="pitch" axis="0 1 0" range="-1 1"/>
          <geom type="sphere" size="0.01" pos="0 0 -0.5" mass="0.01"/></body></body>
    </body></worldbody>
    <actuator><motor joint="yaw"/><motor joint="pitch"/></actuator></mujoco>)";
  auto l = Load(xml);
  RobotMap robot;
  std::string error;
  ASSERT_TRUE(MapRobot(l->m, &robot, &error)) << error;
  ASSERT_EQ(robot.joints.size(), 2u);
  const JointMap& yaw = robot.joints[0];
  const JointMap& pitch = robot.joints[1];
  const double w = 2 * M_PI * 6.0;
  // a yaw axis carries no gravity stiffness: in single support it turns the load (the 10 kg
  // sphere of radius 0.05 m on its axis, 2/5 m r^2) and closes at 3 Hz on that inertia, unless
  // the 6 Hz rule on its own inertia asks more
  const double w3 = 2 * M_PI * 3.0;
  EXPECT_NEAR(yaw.default_kp,
              std::max(0.4 * 10 * 0.05 * 0.05 * w3 * w3, l->m->dof_M0[6] * w * w), 1e-6)
      << "a yaw axis: 3 Hz on the load";
  EXPECT_GT(yaw.default_kp, 2 * l->m->dof_M0[6] * w * w) << "the load's inertia, not its own, binds";
  const double m_c = 10.001;                           // the base and the hip link
  const double h_c = (10 * 1.0 + 0.001 * 0.7) / m_c - 0.7;  // their CoM above the pitch hinge
  EXPECT_NEAR(pitch.default_kp, 2 * m_c * 9.81 * h_c / 2, 1e-9);
  const double own = l->m->dof_M0[7];
  EXPECT_GT(pitch.default_kp, 5 * own * w * w) << "the floor binds";
  EXPECT_LE(pitch.default_kd, 0.25 * own / 0.001 + 1e-12) << "within the explicit step's bound";
  EXPECT_GT(pitch.default_kd, 0);
  // the model's name is cut to the segment header's 31 bytes, not refused
  EXPECT_EQ(robot.name.size(), 31u);
}
}  // namespace
}  // namespace ohrp::model
