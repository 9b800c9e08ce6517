// The inside of hw_emulator (see emulator.h): the boards' state and the loop's objects, shared
// by emulator.cc (set-up, the loop, the report) and emulator_boards.cc (commands in, states out).
// Private to hw_emulator.
#pragma once

#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include "emulator.h"
#include "faults.h"
#include "plant_gap.h"
#include "hw_udp/protocol.h"
#include "hw_udp/socket.h"
#include "robot_model/command_delay.h"
#include "robot_model/model.h"
#include "robot_model/servo.h"
#include "sim_host/contact_choice.h"
#include "sim_host/feet.h"
#include "sim_host/pushes.h"
#include "sim_host/step.h"

namespace ohrp::hw::udp::emu {

// sensor ranges: a saturated sensor reads these (with the sign of its true value)
constexpr double kForceRange = 2000.0;   // [N]
constexpr double kTorqueRange = 300.0;   // [N m]
constexpr double kGyroRange = 8.0;       // [rad/s]
constexpr double kAccelRange = 39.2;     // [m/s^2] (4 g)
constexpr int kLateQueue = 512;          // state packets held back at most
constexpr int kSensorResetCycles = 50;  // a restarted sensor board flags `reset` this long
constexpr int kMaxReceive = 1024;        // datagrams handled per cycle at most
constexpr double kMaxBehind = 0.1;       // further behind than this, real time starts again [s]
constexpr int kForeignFlagPackets = 100; // a board flags `foreign` in this many states after one

inline double Peg(double v, double range) { return v < 0 ? -range : range; }

// one motor board as the emulator plays it
struct MotorBoard {
  int first = 0, count = 0;
  SeqTracker rx;          // command numbering
  uint32_t tx_seq = 0;    // state numbering
  uint32_t ack = 0;       // seq of the last command applied
  bool locked = false;    // after a reset or e-stop: servo-on refused until an all-off command
  bool reset_flag = false;  // locked by a reset (reported as board_flag::kReset)
  bool joint_fault = false;
  double last_valid = -1;   // wall time of the last valid command [s] (-1: none yet)
  bool holding = false;     // holding by itself: no valid command for the hold time
  int foreign_flag = 0;     // states still to flag `foreign`
  uint64_t holds = 0, foreign = 0, jumps = 0;
  uint64_t commands = 0, commands_dropped = 0, states_sent = 0, states_dropped = 0, resets = 0;
};

struct LatePacket {
  double due = 0;
  size_t size = 0;
  uint8_t data[kMaxPacketSize];
};

// Everything the loop touches, allocated once at set-up.
class Emulator {
 public:
  explicit Emulator(const EmulatorOptions& o) : o_(o), rng_(o.seed) {}
  int Run();

 private:
  bool SetUp(int* exit_code);
  void Receive(double now);
  bool FromDriver(const Header& h, const sockaddr_in& from, double now);
  void HoldIdleBoards(double now);
  void ApplyCommand(const CommandPacket& p);
  void ResetBoard(int b);
  int ToServo(int first, int count);
  void ApplyDelayed();
  void EstopChanged();
  void SendStates(double now);  // its stages:
  void SendMotorState(size_t bi, uint64_t t_ns, double now, MotorStatePacket* packet);
  void SendSensorState(uint64_t t_ns, double now);
  void ReadForceSensors(SensorStatePacket* sp);
  void ReadImus(SensorStatePacket* sp);
  void Send(const uint8_t* data, size_t n, double now, bool may_be_late);
  void FlushLate(double now);
  void PollControl();
  void Log();
  void Report(double wall, int exit_code);
  bool Drop() { return faults_.loss > 0 && uniform_(rng_) < faults_.loss; }
  double BaseZ() const { return robot_.base_qpos >= 0 ? d_->qpos[robot_.base_qpos + 2] : 0; }
  double BaseTiltDeg() const;

  const EmulatorOptions& o_;
  std::unique_ptr<model::Scene> scene_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  model::RobotMap robot_;
  std::unique_ptr<model::Servo> servo_;
  std::unique_ptr<contact::SoftFootContact> soft_;  // --contact soft: the soles' spring-dampers
  sim::ContactModel contact_ = sim::ContactModel::kAuto;  // --contact as resolved (reported)
  std::vector<sim::Perturbation> pushes_;           // --push
  std::unique_ptr<sim::PhysicsStep> step_;          // sim_host's step of all the above
  BoardLayout layout_;
  std::vector<MotorBoard> motor_;
  uint32_t sensor_tx_seq_ = 0;
  int sensor_reset_cycles_ = 0;  // > 0: the sensor board restarted lately (reset flag)
  uint64_t sensor_sent_ = 0, sensor_dropped_ = 0;
  int steps_per_cycle_ = 1;
  UdpSocket socket_;
  sockaddr_in peer_{};
  bool have_peer_ = false;      // bound to a driver: its address (peer_) and session
  uint32_t session_ = 0;        // the bound driver's session id
  bool started_ = false;   // the first command arrived: robot time runs
  bool estop_ = false;
  bool servo_on_[shm::kMaxJoints] = {};  // per joint, what the motor boards report
  shm::CommandBlock block_{};
  shm::SensorBlock sensors_{};
  shm::SensorBlock reported_{};  // sensors_ through the sensor gap (SendStates)
  shm::ForceTorque frozen_force_[shm::kMaxForceSensors] = {};
  shm::Imu frozen_imu_[shm::kMaxImus] = {};
  uint32_t frozen_ = 0;    // sensors whose frozen value is taken
  // the gap between the model and the robot (plant_gap.h)
  PlantGap gap_;
  std::unique_ptr<SensorGap> sensor_gap_;
  model::CommandDelay delay_;
  shm::CommandBlock wanted_{};       // the boards' references as accepted (encoders' frame)
  shm::CommandBlock servo_block_{};  // what goes to the servo (joints' frame, delayed)
  uint32_t refused_[shm::kMaxJoints] = {};         // commands refused per joint
  uint32_t servo_rejected_[shm::kMaxJoints] = {};  // the servo's count, last seen
  std::vector<double> q_min_, q_max_;
  FaultState faults_;
  std::vector<FaultEvent> events_;
  std::unique_ptr<ControlFile> control_;
  std::vector<LatePacket> late_;
  int late_count_ = 0;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  uint8_t buf_[kMaxPacketSize + 64];
  FILE* log_ = nullptr;
  // run statistics
  uint64_t cycles_ = 0, overruns_ = 0, resyncs_ = 0, corrupted_ = 0, foreign_ = 0, late_sent_ = 0,
           late_overflow_ = 0, refused_joints_ = 0, send_failed_ = 0;
  double z0_ = 0, z_min_ = 1e9, tilt_max_ = 0;
};

}  // namespace ohrp::hw::udp::emu
