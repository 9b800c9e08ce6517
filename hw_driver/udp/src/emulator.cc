// The hw_emulator loop (see emulator.h).
#include "emulator.h"

#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>

#include "faults.h"
#include "hw_udp/protocol.h"
#include "hw_udp/socket.h"
#include "sim_host/model.h"
#include "sim_host/sensors.h"
#include "sim_host/servo.h"

namespace ohrp::hw::udp {
namespace {

// sensor ranges: a saturated sensor reads these (with the sign of its true value)
constexpr double kForceRange = 2000.0;   // [N]
constexpr double kTorqueRange = 300.0;   // [N m]
constexpr double kGyroRange = 8.0;       // [rad/s]
constexpr double kAccelRange = 39.2;     // [m/s^2] (4 g)
constexpr int kLateQueue = 512;          // state packets held back at most
constexpr int kSensorResetCycles = 50;  // a restarted sensor board flags `reset` this long
constexpr int kMaxReceive = 1024;        // datagrams handled per cycle at most
constexpr double kMaxBehind = 0.1;       // further behind than this, real time starts again [s]

std::atomic<int> g_signal{0};
void OnSignal(int sig) { g_signal.store(sig); }
void OnFatal(const char*) {}

double Now() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

void SleepUntil(double t) {
  timespec ts;
  ts.tv_sec = static_cast<time_t>(t);
  ts.tv_nsec = static_cast<long>((t - static_cast<double>(ts.tv_sec)) * 1e9);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    if (g_signal.load()) return;
  }
}

double Peg(double v, double range) { return v < 0 ? -range : range; }

// one motor board as the emulator plays it
struct MotorBoard {
  int first = 0, count = 0;
  SeqTracker rx;          // command numbering
  uint32_t tx_seq = 0;    // state numbering
  uint32_t ack = 0;       // seq of the last command applied
  bool locked = false;    // after a reset or e-stop: servo-on refused until an all-off command
  bool reset_flag = false;  // locked by a reset (reported as board_flag::kReset)
  bool joint_fault = false;
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
  void Receive();
  void ApplyCommand(const CommandPacket& p);
  void ResetBoard(int b);
  void EstopChanged();
  void SendStates(double now);
  void Send(const uint8_t* data, size_t n, double now, bool may_be_late);
  void FlushLate(double now);
  void PollControl();
  void Log();
  void Report(double wall, int exit_code);
  bool Drop() { return faults_.loss > 0 && uniform_(rng_) < faults_.loss; }
  double BaseZ() const { return robot_.base_qpos >= 0 ? d_->qpos[robot_.base_qpos + 2] : 0; }
  double BaseTiltDeg() const;

  const EmulatorOptions& o_;
  std::unique_ptr<sim::Scene> scene_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  sim::RobotMap robot_;
  std::unique_ptr<sim::Servo> servo_;
  BoardLayout layout_;
  std::vector<MotorBoard> motor_;
  uint32_t sensor_tx_seq_ = 0;
  int sensor_reset_cycles_ = 0;  // > 0: the sensor board restarted lately (reset flag)
  uint64_t sensor_sent_ = 0, sensor_dropped_ = 0;
  int steps_per_cycle_ = 1;
  UdpSocket socket_;
  sockaddr_in peer_{};
  bool have_peer_ = false;
  bool started_ = false;   // the first command arrived: robot time runs
  bool estop_ = false;
  bool servo_on_[shm::kMaxJoints] = {};  // per joint, what the motor boards report
  shm::CommandBlock block_{};
  shm::SensorBlock sensors_{};
  shm::ForceTorque frozen_force_[shm::kMaxForceSensors] = {};
  shm::Imu frozen_imu_[shm::kMaxImus] = {};
  uint32_t frozen_ = 0;    // sensors whose frozen value is taken
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

double Emulator::BaseTiltDeg() const {
  if (robot_.base_qpos < 0) return 0;
  const double* q = d_->qpos + robot_.base_qpos + 3;  // w x y z
  const double c = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);  // z of the base's z axis in the world
  return std::acos(std::fmax(-1.0, std::fmin(1.0, c))) * 180.0 / M_PI;
}

//---------------- set-up ----------------

bool Emulator::SetUp(int* exit_code) {
  *exit_code = kEmuExitUsage;
  std::string error;
  scene_ = sim::Scene::Load(o_.model, &error);
  if (!scene_) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  m_ = scene_->m();
  d_ = scene_->d();
  if (!scene_->Reset(o_.keyframe, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  const double ratio = o_.period / m_->opt.timestep;
  steps_per_cycle_ = static_cast<int>(std::lround(ratio));
  if (steps_per_cycle_ < 1 || std::fabs(ratio - steps_per_cycle_) > 1e-6) {
    std::fprintf(stderr,
                 "hw_emulator: --period %g s must be a whole multiple of the model's timestep "
                 "(%g s)\n", o_.period, m_->opt.timestep);
    return false;
  }
  if (!sim::MapRobot(m_, &robot_, &error)) {
    std::fprintf(stderr, "hw_emulator: %s: %s\n", o_.model.c_str(), error.c_str());
    return false;
  }
  std::vector<std::string> names;
  for (const sim::JointMap& j : robot_.joints) names.push_back(j.name);
  if (o_.boards.empty()) {
    layout_ = DefaultLayout(names);
  } else if (!ParseLayout(o_.boards, static_cast<int>(names.size()), &layout_, &error)) {
    std::fprintf(stderr, "hw_emulator: --boards: %s\n", error.c_str());
    return false;
  }
  if (layout_.nboards() > kMaxBoards) {
    std::fprintf(stderr, "hw_emulator: the robot needs %d boards, more than the protocol's %d; "
                 "give a layout with --boards\n", layout_.nboards(), kMaxBoards);
    return false;
  }
  const int nf = static_cast<int>(robot_.forces.size()), ni = static_cast<int>(robot_.imus.size());
  auto plan = [&](const char* option, const std::vector<std::string>& values) {
    for (const std::string& v : values) {
      if (!ParseEvent(option, v, layout_.nboards(), nf, ni, &events_, &error)) {
        std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
        return false;
      }
    }
    return true;
  };
  if (!plan("--silent", o_.silent) || !plan("--reset", o_.reset) || !plan("--stuck", o_.stuck) ||
      !plan("--saturate", o_.saturate) || !plan("--estop", o_.estop))
    return false;
  faults_.loss = o_.loss;
  faults_.late_rate = o_.late_rate;
  faults_.late_s = o_.late_ms * 1e-3;
  if (!o_.control_file.empty()) control_ = std::make_unique<ControlFile>(o_.control_file);
  late_.resize(kLateQueue);

  // the boards: servos off
  for (const BoardLayout::Range& r : layout_.motor) {
    MotorBoard b;
    b.first = r.first;
    b.count = r.count;
    motor_.push_back(b);
  }
  servo_ = std::make_unique<sim::Servo>(robot_);
  block_.njoint = static_cast<int>(robot_.joints.size());
  for (int i = 0; i < block_.njoint; ++i) block_.joint[i] = shm::JointCommand{};  // kOff
  servo_->Accept(block_);
  mj_forward(m_, d_);
  z0_ = BaseZ();

  if (!o_.log_path.empty()) {
    log_ = std::fopen(o_.log_path.c_str(), "w");
    if (!log_) {
      std::fprintf(stderr, "hw_emulator: cannot write the log '%s': %s\n", o_.log_path.c_str(),
                   std::strerror(errno));
      return false;
    }
    std::fprintf(log_, "time,base_z,tilt_deg,servos_on,silent,stuck,saturated,estop\n");
  }
  if (!socket_.Open(o_.host, o_.port, &error)) {
    std::fprintf(stderr, "hw_emulator: %s\n", error.c_str());
    return false;
  }
  if (!o_.port_file.empty()) {
    const std::string tmp = o_.port_file + ".tmp";
    FILE* f = std::fopen(tmp.c_str(), "w");
    if (!f || std::fprintf(f, "%d\n", socket_.port()) < 0 || std::fclose(f) != 0 ||
        std::rename(tmp.c_str(), o_.port_file.c_str()) != 0) {
      std::fprintf(stderr, "hw_emulator: cannot write the port file '%s'\n", o_.port_file.c_str());
      return false;
    }
  }
  if (!o_.quiet) {
    std::fprintf(stderr,
                 "hw_emulator: robot '%s' (%zu joints, %d F/T, %d IMU) from %s; boards %s + "
                 "sensor board %d on udp %s:%d; period %g s (%d physics steps); loss %g, late %g "
                 "x %g ms; robot time starts with the first command\n",
                 robot_.name.c_str(), robot_.joints.size(), nf, ni, o_.model.c_str(),
                 LayoutString(layout_).c_str(), layout_.sensor_board(), o_.host.c_str(),
                 socket_.port(), o_.period, steps_per_cycle_, o_.loss, o_.late_rate, o_.late_ms);
  }
  *exit_code = kEmuExitOk;
  return true;
}

//---------------- commands in ----------------

void Emulator::Receive() {
  for (int i = 0; i < kMaxReceive; ++i) {  // bounded: at most this many datagrams a cycle
    sockaddr_in from;
    const long n = socket_.Receive(buf_, kMaxPacketSize, &from);
    if (n <= 0) return;
    Header h;
    if (DecodeHeader(buf_, static_cast<size_t>(n), &h) != DecodeError::kOk ||
        h.board >= layout_.nboards()) {
      ++corrupted_;
      continue;
    }
    if (faults_.silent & (1u << h.board)) continue;  // a silent board hears nothing either
    if (h.type == static_cast<uint8_t>(PacketType::kHello)) {
      peer_ = from;
      have_peer_ = true;
      continue;
    }
    if (h.type != static_cast<uint8_t>(PacketType::kCommand) || h.board >= motor_.size()) {
      ++corrupted_;
      continue;
    }
    MotorBoard& b = motor_[h.board];
    if (Drop()) {  // injected loss on the way to the board
      ++b.commands_dropped;
      continue;
    }
    CommandPacket p;
    if (DecodeCommand(buf_, static_cast<size_t>(n), &p) != DecodeError::kOk ||
        p.h.first != b.first || p.h.count != b.count) {
      ++corrupted_;
      continue;
    }
    peer_ = from;
    have_peer_ = true;
    if (!b.rx.Accept(p.h.seq, false)) continue;  // old or duplicate
    ApplyCommand(p);
  }
}

void Emulator::ApplyCommand(const CommandPacket& p) {
  MotorBoard& b = motor_[p.h.board];
  ++b.commands;
  b.ack = p.h.seq;
  bool any_on = false;
  for (int k = 0; k < b.count; ++k) any_on |= p.joint[k].servo_on;
  if (b.locked && !any_on && !estop_) {  // the driver turned every servo off: re-armed
    b.locked = false;
    b.reset_flag = false;
  }
  // the whole block: other boards' joints keep their references
  for (int i = 0; i < block_.njoint; ++i) block_.joint[i] = servo_->reference(i);
  for (int k = 0; k < b.count; ++k) {
    const bool on = p.joint[k].servo_on && !b.locked;
    servo_on_[b.first + k] = on;
    block_.joint[b.first + k] = on ? p.joint[k].cmd : shm::JointCommand{};
  }
  const int refused = servo_->Accept(block_);
  refused_joints_ += refused;
  b.joint_fault = refused > 0;
  if (!started_) {
    started_ = true;
    if (!o_.quiet) std::fprintf(stderr, "hw_emulator: first command; robot time starts\n");
  }
}

void Emulator::ResetBoard(int b) {
  if (b >= static_cast<int>(motor_.size())) {  // the sensor board: its numbering starts again
    sensor_tx_seq_ = 0;
    sensor_reset_cycles_ = kSensorResetCycles;
    return;
  }
  MotorBoard& mb = motor_[b];
  for (int i = 0; i < block_.njoint; ++i) block_.joint[i] = servo_->reference(i);
  for (int k = 0; k < mb.count; ++k) {
    block_.joint[mb.first + k] = shm::JointCommand{};
    servo_on_[mb.first + k] = false;
  }
  servo_->Accept(block_);
  mb.rx = SeqTracker{};
  mb.tx_seq = 0;
  mb.ack = 0;
  mb.locked = true;
  mb.reset_flag = true;
  ++mb.resets;
}

void Emulator::EstopChanged() {
  if (!estop_) return;  // released: the boards stay off until re-armed by an all-off command
  for (int i = 0; i < block_.njoint; ++i) {
    block_.joint[i] = shm::JointCommand{};
    servo_on_[i] = false;
  }
  servo_->Accept(block_);
  for (MotorBoard& b : motor_) b.locked = true;
}

//---------------- states out ----------------

void Emulator::Send(const uint8_t* data, size_t n, double now, bool may_be_late) {
  if (may_be_late && faults_.late_rate > 0 && uniform_(rng_) < faults_.late_rate) {
    if (late_count_ < kLateQueue) {
      for (LatePacket& l : late_) {
        if (l.size == 0) {
          l.due = now + faults_.late_s;
          l.size = n;
          std::memcpy(l.data, data, n);
          ++late_count_;
          return;
        }
      }
    }
    ++late_overflow_;  // the queue is full: sent on time
  }
  if (!socket_.SendTo(peer_, data, n)) ++send_failed_;
}

void Emulator::FlushLate(double now) {
  if (late_count_ == 0) return;
  for (LatePacket& l : late_) {
    if (l.size == 0 || l.due > now) continue;
    if (have_peer_ && !socket_.SendTo(peer_, l.data, l.size)) ++send_failed_;
    l.size = 0;
    --late_count_;
    ++late_sent_;
  }
}

void Emulator::SendStates(double now) {
  const uint64_t t_ns = static_cast<uint64_t>(std::llround(d_->time * 1e9));
  MotorStatePacket mp;
  for (size_t bi = 0; bi < motor_.size(); ++bi) {
    MotorBoard& b = motor_[bi];
    const uint32_t seq = b.tx_seq++;
    if (faults_.silent & (1u << bi)) continue;
    mp.h = Header{};
    mp.h.board = static_cast<uint8_t>(bi);
    mp.h.first = static_cast<uint8_t>(b.first);
    mp.h.count = static_cast<uint8_t>(b.count);
    mp.h.seq = seq;
    mp.h.ack = b.ack;
    mp.h.time_ns = t_ns;
    mp.h.flags = (b.reset_flag ? board_flag::kReset : 0) | (b.joint_fault ? board_flag::kJointFault : 0);
    for (int k = 0; k < b.count; ++k) {
      const int j = b.first + k;
      mp.joint[k].servo_on = servo_on_[j];
      mp.joint[k].fault = servo_->rejected_per_joint()[j] > 0 ? 1 : 0;
      mp.joint[k].q = sensors_.q[j];
      mp.joint[k].dq = sensors_.dq[j];
      mp.joint[k].tau = sensors_.tau[j];
    }
    if (Drop()) {
      ++b.states_dropped;
      continue;
    }
    const size_t n = EncodeMotorState(mp, buf_);
    Send(buf_, n, now, true);
    ++b.states_sent;
  }

  // the sensor board, with its stuck and saturated sensors
  const int sb = layout_.sensor_board();
  const uint32_t seq = sensor_tx_seq_++;
  if (faults_.silent & (1u << sb)) return;
  SensorStatePacket sp{};
  sp.h.board = static_cast<uint8_t>(sb);
  sp.h.count = static_cast<uint8_t>(robot_.forces.size());
  sp.h.first = static_cast<uint8_t>(robot_.imus.size());
  sp.h.seq = seq;
  sp.h.time_ns = t_ns;
  for (int i = 0; i < sp.h.count; ++i) {
    shm::ForceTorque f = sensors_.force[i];
    if (faults_.stuck & (1u << i)) {
      if (!(frozen_ & (1u << i))) frozen_force_[i] = f;
      frozen_ |= 1u << i;
      f = frozen_force_[i];
    } else {
      frozen_ &= ~(1u << i);
    }
    if (faults_.saturated & (1u << i)) {
      for (double& v : f.force) v = Peg(v, kForceRange);
      for (double& v : f.torque) v = Peg(v, kTorqueRange);
    }
    sp.force[i] = f;
  }
  for (int i = 0; i < sp.h.first; ++i) {
    const uint32_t bit = 1u << (8 + i);
    shm::Imu u = sensors_.imu[i];
    if (faults_.stuck & bit) {
      if (!(frozen_ & bit)) frozen_imu_[i] = u;
      frozen_ |= bit;
      u = frozen_imu_[i];
    } else {
      frozen_ &= ~bit;
    }
    if (faults_.saturated & bit) {
      for (double& v : u.gyro) v = Peg(v, kGyroRange);
      for (double& v : u.accel) v = Peg(v, kAccelRange);
    }
    sp.imu[i] = u;
  }
  if (sensor_reset_cycles_ > 0) --sensor_reset_cycles_;
  sp.h.flags = (sensor_reset_cycles_ > 0 ? board_flag::kReset : 0) |
               (faults_.stuck ? board_flag::kSensorStuck : 0) |
               (faults_.saturated ? board_flag::kSensorSaturated : 0) |
               (faults_.estop ? board_flag::kEmergencyStop : 0);
  if (Drop()) {
    ++sensor_dropped_;
    return;
  }
  const size_t n = EncodeSensorState(sp, buf_);
  Send(buf_, n, now, true);
  ++sensor_sent_;
}

//---------------- faults at run time, log, report ----------------

void Emulator::PollControl() {
  std::string error;
  for (const std::string& line : control_->NewLines()) {
    if (!ApplyControlLine(line, layout_.nboards(), static_cast<int>(robot_.forces.size()),
                          static_cast<int>(robot_.imus.size()), &faults_, &error)) {
      std::fprintf(stderr, "hw_emulator: %s: %s\n", control_->path().c_str(), error.c_str());
    } else if (!o_.quiet && !line.empty() && line[0] != '#') {
      std::fprintf(stderr, "hw_emulator: t=%.3f s: control '%s'\n", d_->time, line.c_str());
    }
  }
}

void Emulator::Log() {
  int on = 0;
  for (int i = 0; i < block_.njoint; ++i) on += servo_on_[i] ? 1 : 0;
  std::fprintf(log_, "%.4f,%.5f,%.3f,%d,%u,%u,%u,%d\n", d_->time, BaseZ(), BaseTiltDeg(), on,
               faults_.silent, faults_.stuck, faults_.saturated, faults_.estop ? 1 : 0);
}

void Emulator::Report(double wall, int exit_code) {
  uint64_t cmds = 0, cmd_lost = 0, cmd_dropped = 0, sent = sensor_sent_, dropped = sensor_dropped_,
           resets = 0;
  for (const MotorBoard& b : motor_) {
    cmds += b.commands;
    cmd_lost += b.rx.lost();
    cmd_dropped += b.commands_dropped;
    sent += b.states_sent;
    dropped += b.states_dropped;
    resets += b.resets;
  }
  std::fprintf(stderr,
               "hw_emulator: robot time %.3f s in %.3f s wall, %llu cycles, %llu overruns, %llu "
               "resyncs; base height %.4f m at start, %.4f m at end, %.4f m lowest; tilt %.2f deg "
               "at most\n"
               "hw_emulator: commands applied %llu, lost on the way %llu (%llu injected), refused "
               "joints %llu; states sent %llu, dropped %llu (injected), late %llu; corrupted %llu; "
               "board resets %llu\n",
               d_->time, wall, static_cast<unsigned long long>(cycles_),
               static_cast<unsigned long long>(overruns_), static_cast<unsigned long long>(resyncs_),
               z0_, BaseZ(), z_min_ > 1e8 ? BaseZ() : z_min_, tilt_max_,
               static_cast<unsigned long long>(cmds), static_cast<unsigned long long>(cmd_lost),
               static_cast<unsigned long long>(cmd_dropped),
               static_cast<unsigned long long>(refused_joints_), static_cast<unsigned long long>(sent),
               static_cast<unsigned long long>(dropped), static_cast<unsigned long long>(late_sent_),
               static_cast<unsigned long long>(corrupted_), static_cast<unsigned long long>(resets));
  // one machine-readable line (always printed, also with --quiet)
  std::fprintf(stderr,
               "hw_emulator: result exit=%d time=%.4f base_z_start=%.5f base_z_end=%.5f "
               "base_z_min=%.5f tilt_max_deg=%.3f commands=%llu commands_lost=%llu "
               "commands_dropped=%llu states_sent=%llu states_dropped=%llu late=%llu "
               "send_failed=%llu overruns=%llu\n",
               exit_code, d_->time, z0_, BaseZ(), z_min_ > 1e8 ? BaseZ() : z_min_, tilt_max_,
               static_cast<unsigned long long>(cmds), static_cast<unsigned long long>(cmd_lost),
               static_cast<unsigned long long>(cmd_dropped),
               static_cast<unsigned long long>(sent), static_cast<unsigned long long>(dropped),
               static_cast<unsigned long long>(late_sent_),
               static_cast<unsigned long long>(send_failed_),
               static_cast<unsigned long long>(overruns_));
}

//---------------- the loop ----------------

int Emulator::Run() {
  int exit_code = kEmuExitOk;
  if (!SetUp(&exit_code)) return exit_code;
  const double wall_start = Now();
  double deadline = wall_start;
  double next_control = wall_start;
  const int badqacc = d_->warning[mjWARN_BADQACC].number;
  while (!g_signal.load()) {
    if (o_.duration > 0 && d_->time >= o_.duration - 0.5 * m_->opt.timestep) break;
    const double now = Now();
    if (control_ && now >= next_control) {
      next_control = now + kControlPollPeriod;
      PollControl();
    }
    ApplyDue(d_->time, &events_, &faults_);
    if (faults_.reset_request) {
      for (int b = 0; b < layout_.nboards(); ++b)
        if (faults_.reset_request & (1u << b)) ResetBoard(b);
      faults_.reset_request = 0;
    }
    if (faults_.estop != estop_) {
      estop_ = faults_.estop;
      EstopChanged();
    }

    Receive();
    if (!started_ && o_.wait_driver > 0 && now - wall_start > o_.wait_driver) {
      std::fprintf(stderr,
                   "hw_emulator: no command packet within %g s on udp %s:%d; start the driver "
                   "(e.g. hw_driver --io lib/libohrp_io_udp.so --io-arg port=%d) or raise "
                   "--wait-driver\n", o_.wait_driver, o_.host.c_str(), socket_.port(), socket_.port());
      exit_code = kEmuExitNoDriver;
      break;
    }

    // physics, the motor boards' PD at every step
    if (started_) {
      for (int s = 0; s < steps_per_cycle_; ++s) {
        servo_->Apply(m_, d_);
        mj_step(m_, d_);
      }
      bool finite = true;
      for (int i = 0; i < m_->nq; ++i) finite &= std::isfinite(d_->qpos[i]);
      if (!finite || d_->warning[mjWARN_BADQACC].number != badqacc) {
        std::fprintf(stderr, "hw_emulator: the simulation diverged at t=%.3f s\n", d_->time);
        exit_code = kEmuExitDiverged;
        break;
      }
      z_min_ = std::fmin(z_min_, BaseZ());
      tilt_max_ = std::fmax(tilt_max_, BaseTiltDeg());
    }
    sim::FillSensors(robot_, m_, d_, &sensors_);
    ++cycles_;

    const double sent_at = Now();
    if (have_peer_) SendStates(sent_at);
    FlushLate(sent_at);
    if (log_ && cycles_ % static_cast<uint64_t>(o_.log_every) == 0) Log();

    // absolute deadlines; far behind (a stalled machine), real time starts again
    deadline += o_.period;
    const double after = Now();
    if (after > deadline + o_.period) ++overruns_;
    if (after > deadline + kMaxBehind) {
      deadline = after;
      ++resyncs_;
    }
    SleepUntil(deadline);
  }
  const double wall = Now() - wall_start;
  if (g_signal.load() && exit_code == kEmuExitOk) {
    exit_code = kEmuExitInterrupted;
    if (!o_.quiet)
      std::fprintf(stderr, "hw_emulator: interrupted (signal %d); shutting down\n", g_signal.load());
  }
  if (log_) std::fclose(log_);
  log_ = nullptr;
  Report(wall, exit_code);
  return exit_code;
}

}  // namespace

int RunEmulator(const EmulatorOptions& options) {
  sim::InstallMujocoHandlers(OnFatal);
  struct sigaction sa {};
  sa.sa_handler = OnSignal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  Emulator e(options);
  return e.Run();
}

}  // namespace ohrp::hw::udp
