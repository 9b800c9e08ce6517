// Tests hw_emulator's gap between the model and the robot (plant_gap.h): parsing and its
// refusals, the delay ring, the sensors' bias and noise, and the friction and armature set on a
// single hinge against their closed forms.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <memory>

#include "common/scratch.h"
#include "plant_gap.h"

namespace ohrp::hw::udp {
namespace {

const std::vector<std::string> kNames = {"HIP", "KNEE", "ELBOW"};
constexpr double kPeriod = 0.002;

TEST(PlantGap, OptionsAreParsedAndLaterOnesOverride) {
  GapOptions o;
  o.friction = {"all=0.5,0.1", "KNEE=2,0.3"};
  o.armature = {"2=0.01"};
  o.encoder_bias = {"all=-0.02", "ELBOW=0.05"};
  o.delay_ms = 6;
  o.encoder_noise = 1e-4;
  o.imu_bias = "0.01,0.2";
  o.imu_noise = "0.001,0.05";
  o.ft_noise = "1.5,0.2";
  PlantGap g;
  std::string e;
  ASSERT_TRUE(ParseGap(o, kNames, kPeriod, &g, &e)) << e;
  EXPECT_EQ(g.joint[0].coulomb, 0.5);
  EXPECT_EQ(g.joint[1].coulomb, 2.0);
  EXPECT_EQ(g.joint[1].viscous, 0.3);
  EXPECT_EQ(g.joint[2].viscous, 0.1);
  EXPECT_EQ(g.joint[2].armature, 0.01);
  EXPECT_EQ(g.joint[0].armature, 0.0);
  EXPECT_EQ(g.joint[0].bias, -0.02);
  EXPECT_EQ(g.joint[2].bias, 0.05);
  EXPECT_EQ(g.delay_cycles, 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(g.gyro_bias[k], 0.01);
    EXPECT_EQ(g.accel_bias[k], 0.2);
  }
  EXPECT_EQ(g.accel_noise, 0.05);
  EXPECT_EQ(g.force_noise, 1.5);
  EXPECT_EQ(g.torque_noise, 0.2);
  o = GapOptions{};
  o.imu_bias = "1,2,3,4,5,6";
  ASSERT_TRUE(ParseGap(o, kNames, kPeriod, &g, &e)) << e;
  EXPECT_EQ(g.gyro_bias[2], 3.0);
  EXPECT_EQ(g.accel_bias[0], 4.0);
  EXPECT_EQ(DescribeGap(g), "IMU bias");
  ASSERT_TRUE(ParseGap(GapOptions{}, kNames, kPeriod, &g, &e)) << e;
  EXPECT_EQ(DescribeGap(g), "none");
}

TEST(PlantGap, BadValuesAndNamesAreRefusedWithTheReason) {
  struct Case {
    GapOptions o;
    const char* says;
  };
  std::vector<Case> cases(10);
  cases[0].o.friction = {"WRIST=1,0"};
  cases[0].says = "no joint 'WRIST'";
  cases[1].o.friction = {"all=-1,0"};
  cases[1].says = "COULOMB,VISCOUS";
  cases[2].o.friction = {"all=1"};
  cases[2].says = "COULOMB,VISCOUS";
  cases[3].o.armature = {"3=0.1"};
  cases[3].says = "no joint '3'";
  cases[4].o.encoder_bias = {"KNEE=x"};
  cases[4].says = "[rad]";
  cases[5].o.delay_ms = 3;  // 1.5 cycles of 2 ms
  cases[5].says = "whole number of board cycles";
  cases[6].o.delay_ms = -2;
  cases[6].says = "--delay-ms";
  cases[7].o.imu_noise = "0.1";
  cases[7].says = "--imu-noise";
  cases[8].o.ft_noise = "1,-1";
  cases[8].says = "--ft-noise";
  cases[9].o.imu_bias = "1,2,3";
  cases[9].says = "GX,GY,GZ,AX,AY,AZ";
  for (const Case& c : cases) {
    PlantGap g;
    std::string e;
    EXPECT_FALSE(ParseGap(c.o, kNames, kPeriod, &g, &e)) << c.says;
    EXPECT_NE(e.find(c.says), std::string::npos) << e;
  }
}

TEST(SensorGap, BiasAndNoiseHaveTheirMeanAndStd) {
  PlantGap g;
  g.joint.assign(2, JointGap{});
  g.joint[1].bias = 0.03;
  g.encoder_noise = 0.002;
  g.gyro_bias[1] = 0.05;
  g.accel_noise = 0.1;
  g.force_noise = 2.0;
  SensorGap s(g, 1, 1, {}, 42);
  ohrp::model::RobotMap robot;  // two joints, one IMU, one F/T sensor
  robot.joints.resize(2);
  robot.imus.resize(1);
  robot.forces.resize(1);
  constexpr int kN = 20000;
  double sum = 0, sum2 = 0, gyro = 0, acc2 = 0, f2 = 0;
  for (int i = 0; i < kN; ++i) {
    shm::SensorBlock b{};
    b.q[1] = 0.7;
    s.Apply(robot, &b);
    const double e = b.q[1] - 0.7;
    sum += e;
    sum2 += e * e;
    gyro += b.imu[0].gyro[1];
    acc2 += b.imu[0].accel[2] * b.imu[0].accel[2];
    EXPECT_EQ(b.imu[0].gyro[0], 0.0);  // no noise asked on the rates
    EXPECT_EQ(b.dq[1], 0.0);            // nor on the velocities
    f2 += b.force[0].force[0] * b.force[0].force[0];
    EXPECT_EQ(b.force[0].torque[2], 0.0);
  }
  const double mean = sum / kN, std = std::sqrt(sum2 / kN - mean * mean);
  // mean within 4 standard errors, std within 4 % (its standard error is 1/sqrt(2N) = 0.5 %)
  EXPECT_NEAR(mean, 0.03, 4 * 0.002 / std::sqrt(kN));
  EXPECT_NEAR(std, 0.002, 0.04 * 0.002);
  EXPECT_NEAR(gyro / kN, 0.05, 1e-12);
  EXPECT_NEAR(std::sqrt(acc2 / kN), 0.1, 0.004);
  EXPECT_NEAR(std::sqrt(f2 / kN), 2.0, 0.08);
}

// A hinge about the vertical (no gravity torque) with inertia 0.2 kg m^2 about its axis.
constexpr double kInertia = 0.2;
const char* kHinge = R"(<mujoco>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody><body><joint name="J" type="hinge" axis="0 0 1"/>
    <inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.2"/></body></worldbody>
</mujoco>)";

struct Hinge {
  std::unique_ptr<mjModel, void (*)(mjModel*)> m{nullptr, mj_deleteModel};
  std::unique_ptr<mjData, void (*)(mjData*)> d{nullptr, mj_deleteData};
  explicit Hinge(const GapOptions& o) {
    const std::string path = ohrp::testing::ScratchFile("hinge", kHinge, ".xml");
    char err[500] = "";
    m.reset(mj_loadXML(path.c_str(), nullptr, err, sizeof(err)));
    EXPECT_TRUE(m) << err;
    PlantGap g;
    std::string e;
    EXPECT_TRUE(ParseGap(o, {"J"}, 0.001, &g, &e)) << e;
    d.reset(mj_makeData(m.get()));
    ApplyGapToModel(g, {0}, m.get(), d.get());
  }
  // velocity after `t` seconds under the constant torque `tau`
  double Run(double tau, double t) {
    for (int i = 0; i < std::lround(t / m->opt.timestep); ++i) {
      d->qfrc_applied[0] = tau;
      mj_step(m.get(), d.get());
    }
    return d->qvel[0];
  }
};

TEST(PlantGapOnTheModel, ArmatureAddsToTheInertia) {
  GapOptions o;
  o.armature = {"J=0.05"};
  Hinge h(o);
  h.d->qfrc_applied[0] = 1.0;
  mj_forward(h.m.get(), h.d.get());
  EXPECT_NEAR(h.d->qacc[0], 1.0 / (kInertia + 0.05), 1e-9);
}

TEST(PlantGapOnTheModel, ViscousFrictionGivesTheTerminalVelocity) {
  GapOptions o;
  o.friction = {"J=0,0.5"};
  Hinge h(o);
  // time constant I/b = 0.4 s: after 4 s (10 of them) the velocity is tau/b
  EXPECT_NEAR(h.Run(0.3, 4.0), 0.3 / 0.5, 1e-3 * 0.6);
}

TEST(PlantGapOnTheModel, CoulombFrictionHoldsBelowItAndSubtractsAbove) {
  GapOptions o;
  o.friction = {"J=1.0,0"};
  Hinge below(o), above(o);
  const double v_below = below.Run(0.8, 1.0);  // 80 % of the friction: held
  const double v_above = above.Run(1.5, 1.0);  // (1.5 - 1.0) / I after 1 s
  std::printf("[ figures  ] Coulomb 1 N m: at 0.8 N m the hinge creeps at %.3g rad/s (free: "
              "%.3g rad/s after 1 s); at 1.5 N m it reaches %.4f rad/s, closed form %.4f\n",
              v_below, 0.8 / kInertia, v_above, 0.5 / kInertia);
  // MuJoCo's friction is a soft constraint (model::kFrictionImpedance, robot_model/joint_params.h)
  EXPECT_LT(std::fabs(v_below), 2e-4 * 0.8 / kInertia);
  EXPECT_NEAR(v_above, 0.5 / kInertia, 0.01 * 0.5 / kInertia);
}

}  // namespace
}  // namespace ohrp::hw::udp
