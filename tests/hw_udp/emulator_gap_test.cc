// Tests hw_emulator's gap between the model and the robot (plant_gap.h) as a process, through
// the udp plugin, against closed forms: the sensors' bias and noise on the robot at rest (its
// time stands still until the first command, so what the boards report minus the simulation is
// the bias plus the noise), the actuator delay as the lag of a step, Coulomb friction holding a
// joint against gravity, and the refusals.
#include <algorithm>
#include <cstdio>

#include "emulator_fixture.h"
#include "robot_model/sensors.h"

namespace ohrp::hw::udp {
namespace {

using namespace emulator_test;  // NOLINT(build/namespaces): the fixture of these tests

// the sensors as the model gives them at the scene's initial state (what the emulator computes
// before its robot time starts)
shm::SensorBlock SimulatedAtRest() {
  std::string e;
  auto scene = model::Scene::Load(kScene, &e);
  EXPECT_TRUE(scene) << e;
  model::RobotMap map;
  EXPECT_TRUE(model::MapRobot(scene->m(), &map, &e)) << e;
  EXPECT_TRUE(scene->Reset("", &e)) << e;
  mj_forward(scene->m(), scene->d());
  shm::SensorBlock s{};
  model::FillSensors(map, scene->m(), scene->d(), &s);
  return s;
}

// a joint's index in the robot's (and the plugin's) order
int Joint(const std::string& name) {
  const auto& names = Hrp1s().config.joint_names;
  const auto it = std::find(names.begin(), names.end(), name);
  EXPECT_NE(it, names.end()) << name;
  return static_cast<int>(it - names.begin());
}

struct Moments {
  double n = 0, sum = 0, sum2 = 0;
  void Add(double x) { n += 1, sum += x, sum2 += x * x; }
  double mean() const { return sum / n; }
  double std() const { return std::sqrt(std::fmax(0.0, sum2 / n - mean() * mean())); }
};

class EmulatorGapTest : public EmulatorTest {};

TEST_F(EmulatorGapTest, SensorsReadTheSimulationPlusTheBiasAndNoiseAsked) {
  constexpr double kBias = 0.01, kElbowBias = -0.02, kNoise = 0.001;
  const int elbow = Joint("LARM_ELBOW");
  const int port = Start({"--duration", "0.2", "--encoder-bias", "all=0.01", "--encoder-bias",
                          "LARM_ELBOW=-0.02", "--encoder-noise", "0.001", "--imu-bias",
                          "0.02,0.3", "--imu-noise", "0.002,0.05", "--ft-noise", "1.0,0.1",
                          // and joints unlike the model's, which the sensors at rest do not see
                          "--armature", "all=1", "--friction", "all=0.2,0.5"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  const shm::SensorBlock sim = SimulatedAtRest();
  // the robot at rest (no command yet): every state packet is the same simulated state
  Moments q_other, q_elbow, gyro, accel, force, torque;
  uint64_t last_received = 0;
  const auto t0 = Clock::now();
  while (q_other.n < 28 * 400 && Since(t0) < kMaxWall) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    io_.read(&state_);
    const uint64_t received = io_.stats().board[0].received;
    if (received == last_received || io_.stats().board[io_.layout().sensor_board()].received == 0)
      continue;  // no new packet since the last look
    last_received = received;
    for (int j = 0; j < 29; ++j) (j == elbow ? q_elbow : q_other).Add(state_.q[j] - sim.q[j]);
    for (int k = 0; k < 3; ++k) {
      gyro.Add(state_.imu[0].gyro[k] - sim.imu[0].gyro[k]);
      accel.Add(state_.imu[0].accel[k] - sim.imu[0].accel[k]);
      force.Add(state_.force[0].force[k] - sim.force[0].force[k]);
      torque.Add(state_.force[0].torque[k] - sim.force[0].torque[k]);
    }
  }
  ASSERT_GE(q_other.n, 28 * 400);
  std::printf("[ figures  ] at rest, reported - simulated over %.0f packets: encoders %.5f +- "
              "%.5f rad (asked 0.01 +- 0.001), elbow %.5f (asked -0.02); gyro %.4f +- %.4f "
              "(0.02 +- 0.002), accel %.3f +- %.4f (0.3 +- 0.05), force 0 %.3f +- %.3f (0 +- 1), "
              "torque %.4f +- %.4f (0 +- 0.1)\n",
              q_elbow.n, q_other.mean(), q_other.std(), q_elbow.mean(), gyro.mean(), gyro.std(),
              accel.mean(), accel.std(), force.mean(), force.std(), torque.mean(), torque.std());
  // means within 5 standard errors, stds within 10 % (standard error 1/sqrt(2n) < 3.6 %)
  auto expect = [](const Moments& m, double bias, double std, const char* what) {
    EXPECT_NEAR(m.mean(), bias, 5 * std / std::sqrt(m.n)) << what;
    EXPECT_NEAR(m.std(), std, 0.1 * std) << what;
  };
  expect(q_other, kBias, kNoise, "encoders");
  expect(q_elbow, kElbowBias, kNoise, "elbow encoder");
  expect(gyro, 0.02, 0.002, "gyro");
  expect(accel, 0.3, 0.05, "accel");
  expect(force, 0.0, 1.0, "force");
  expect(torque, 0.0, 0.1, "torque");
  // holding the biased reading holds the robot where it is: it stands (with the joints'
  // friction and armature too)
  ASSERT_EQ(Drive(), 0) << Stderr();
  EXPECT_GT(Result()["base_z_end"], 0.70) << Stderr();
}

TEST_F(EmulatorGapTest, TheActuatorDelayShowsAsTheLagOfAStep) {
  double lag[2] = {};
  const double delay_ms[2] = {0, 20};
  for (int k = 0; k < 2; ++k) {
    const int port = Start({"--duration", "0.8", "--delay-ms", k ? "20" : "0"});
    ASSERT_GT(port, 0);
    OpenIo(port, {"timeout_ms=500"});
    // the robot time (state packets) between a step of LARM_SHOULDER_P's reference by 0.05 rad
    // at 0.5 s and the first state that shows it moving
    const int kJoint = Joint("LARM_SHOULDER_P");
    double t_cmd = -1, t_move = -1, q0 = 0;
    ASSERT_EQ(Drive([&](const IoState& s, IoCommand* c) {
                const double now = s.time_ns * 1e-9;
                if (t_cmd < 0 && now >= 0.5) {
                  t_cmd = now;  // the newest state when the step goes out
                  q0 = s.q[kJoint];
                  c->joint[kJoint].q_ref += 0.05;
                } else if (t_cmd >= 0 && t_move < 0 && s.q[kJoint] - q0 > 2e-4) {
                  t_move = now;
                }
              }),
              0)
        << Stderr();
    lag[k] = t_move < 0 || t_cmd < 0 ? -1 : t_move - t_cmd;
    io_.close();
    ASSERT_GT(lag[k], 0) << "the joint never moved\n" << Stderr();
  }
  std::printf("[ figures  ] step of LARM_SHOULDER_P: first motion %.1f ms after the step went "
              "out with no delay, %.1f ms with --delay-ms 20 (difference %.1f ms)\n",
              1e3 * lag[0], 1e3 * lag[1], 1e3 * (lag[1] - lag[0]));
  // the delay is whole board cycles of robot time; the transport adds a cycle or two either way
  // (a loaded machine may add more to one run: the upper bound is looser)
  EXPECT_GE(lag[1], 1e-3 * delay_ms[1]);
  EXPECT_LE(lag[1], 1e-3 * delay_ms[1] + 0.008);
  EXPECT_LE(lag[0], 0.008);
}

// With a long delay the commands pending in the ring must not undo an e-stop: the servos go off
// at once and stay off.
TEST_F(EmulatorGapTest, AnEstopActsAtOnceThroughTheActuatorDelay) {
  const int port = Start({"--duration", "1.0", "--delay-ms", "200", "--estop", "0.5"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  double on_at = -1, off_at = -1, back_on_at = -1;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand*) {
              const double t = s.time_ns * 1e-9;
              if (on_at < 0 && s.servo_on[0]) on_at = t;
              if (off_at < 0 && on_at >= 0 && !s.servo_on[0]) off_at = t;
              if (off_at >= 0 && back_on_at < 0 && s.servo_on[0]) back_on_at = t;
            }),
            0)
      << Stderr();
  std::printf("[ figures  ] --delay-ms 200: servos reported on at %.3f s, e-stop at 0.5 s: off "
              "at %.3f s\n", on_at, off_at);
  // at once, not 200 ms later (the driver's view lags the boards by a few cycles: 6 ms seen)
  EXPECT_GE(off_at, 0.5);
  EXPECT_LT(off_at, 0.5 + 0.02);
  EXPECT_LT(back_on_at, 0) << "a pending command turned a servo on after the e-stop";
}

TEST_F(EmulatorGapTest, CoulombFrictionHoldsAJointAgainstATorqueBelowIt) {
  // half-sitting, elbows bent: gravity pulls the forearms; the left elbow gets 10 N m of
  // Coulomb friction, the right none; both servos go off at 0.5 s
  const int kLeft = Joint("LARM_ELBOW"), kRight = Joint("RARM_ELBOW");
  const int port = Start({"--duration", "1.0", "--keyframe", "halfsit", "--friction",
                          "LARM_ELBOW=10,0"});
  ASSERT_GT(port, 0);
  OpenIo(port, {"timeout_ms=500"});
  double q_off[2] = {}, tau_hold[2] = {};
  bool off = false;
  ASSERT_EQ(Drive([&](const IoState& s, IoCommand* c) {
              if (!off && s.time_ns >= 500000000) {
                off = true;
                q_off[0] = s.q[kLeft], q_off[1] = s.q[kRight];
                tau_hold[0] = s.tau[kLeft], tau_hold[1] = s.tau[kRight];
              }
              if (off) c->servo_on[kLeft] = c->servo_on[kRight] = false;
            }),
            0)
      << Stderr();
  const double moved_left = state_.q[kLeft] - q_off[0], moved_right = state_.q[kRight] - q_off[1];
  std::printf("[ figures  ] elbows let go at 0.5 s holding %.2f / %.2f N m: in 0.5 s the left "
              "(Coulomb 10 N m) moved %.2g rad, the right (none) %.4f rad (free, closed form %.4f)\n",
              tau_hold[0], tau_hold[1], moved_left, moved_right,
              std::fabs(tau_hold[1]) * 0.25 / 24.0);
  // the torque gravity puts on the elbows is what the right servo held (the left's friction
  // carried part of it already): below the left's friction, and not nothing
  EXPECT_LT(std::fabs(tau_hold[1]), 10.0);
  EXPECT_GT(std::fabs(tau_hold[1]), 0.5);
  EXPECT_LT(std::fabs(moved_left), 1e-4);
  // the right one accelerates from rest by that torque through the elbow's inertia, mostly the
  // model's armature of 12 kg m^2 (the forearm's own inertia about the axis is < 1 % of it):
  // tau t^2 / (2 I) over 0.5 s, within 10 %
  const double closed_form = std::fabs(tau_hold[1]) * 0.25 / (2 * 12.0);
  EXPECT_NEAR(std::fabs(moved_right), closed_form, 0.1 * closed_form);
}

TEST_F(EmulatorGapTest, BadGapOptionsAreRefusedBeforeRunning) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--friction", "LARM_ELBOWX=1,0"}, "no joint 'LARM_ELBOWX'"},
      {{"--friction", "all=1"}, "COULOMB,VISCOUS"},
      {{"--armature", "all=-0.1"}, "non-negative"},
      {{"--delay-ms", "2.5"}, "whole number of board cycles"},
      {{"--encoder-bias", "29=0.1"}, "no joint '29'"},
      {{"--imu-noise", "0.1"}, "--imu-noise"},
  };
  for (const auto& [args, says] : cases) {
    std::vector<std::string> a = {"--model", kScene};
    a.insert(a.end(), args.begin(), args.end());
    Spawn(a);
    EXPECT_EQ(Wait(), 2) << args[0];
    EXPECT_NE(Stderr().find(says), std::string::npos) << Stderr();
  }
}

}  // namespace
}  // namespace ohrp::hw::udp
