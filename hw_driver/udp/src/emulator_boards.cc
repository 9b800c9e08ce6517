// hw_emulator's boards: command packets in, state packets out, through the injected faults
// (see emulator.h, faults.h and PROTOCOL.md).
#include <cstring>

#include "emulator_impl.h"
#include "robot_model/sensors.h"

namespace ohrp::hw::udp::emu {

//---------------- commands in ----------------

// Whether a hello or command comes from the driver the boards are bound to (PROTOCOL.md,
// "Sessions"). The first hello binds them; a hello of another session or address rebinds them
// only when every motor board has been without a valid command for the hold time (the driver
// is gone: a new one may connect). Anything else is foreign: refused, counted, flagged.
bool Emulator::FromDriver(const Header& h, const sockaddr_in& from, double now) {
  const bool same = have_peer_ && h.ack == session_ && from.sin_addr.s_addr == peer_.sin_addr.s_addr &&
                    from.sin_port == peer_.sin_port;
  if (same) return true;
  if (h.type == static_cast<uint8_t>(PacketType::kHello) && h.ack != 0) {
    bool idle = true;
    for (const MotorBoard& b : motor_) idle &= b.last_valid < 0 || now - b.last_valid > o_.hold_ms * 1e-3;
    if (!have_peer_ || idle) {
      peer_ = from;
      session_ = h.ack;
      have_peer_ = true;
      for (MotorBoard& b : motor_) {
        b.rx = SeqTracker{};  // a new driver numbers from its start
        b.foreign_flag = 0;   // its own packets refused before the binding are not foreign
      }
      return true;
    }
  }
  ++foreign_;
  if (h.board < motor_.size()) {
    ++motor_[h.board].foreign;
    motor_[h.board].foreign_flag = kForeignFlagPackets;
  }
  return false;
}

void Emulator::Receive(double now) {
  for (int i = 0; i < kMaxReceive; ++i) {  // bounded: at most this many datagrams a cycle
    sockaddr_in from;
    const long n = socket_.Receive(buf_, kMaxPacketSize, &from);
    if (n == kNoDatagram || n == kReceiveFailed) return;  // an empty datagram is corrupted below
    Header h;
    if (DecodeHeader(buf_, static_cast<size_t>(n), &h) != DecodeError::kOk ||
        h.board >= layout_.nboards()) {
      ++corrupted_;
      continue;
    }
    if (faults_.silent & (1u << h.board)) continue;  // a silent board hears nothing either
    if (h.type == static_cast<uint8_t>(PacketType::kHello)) {
      FromDriver(h, from, now);
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
    if (!FromDriver(p.h, from, now)) continue;
    const uint64_t jumps = b.rx.jumps();
    if (!b.rx.Accept(p.h.seq, false)) {  // old, duplicate or a jump: refused
      if (b.rx.jumps() != jumps) {
        ++b.jumps;
        b.foreign_flag = kForeignFlagPackets;
      }
      continue;
    }
    b.last_valid = now;
    b.holding = false;
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
  block_ = wanted_;
  for (int k = 0; k < b.count; ++k) {
    const bool on = p.joint[k].servo_on && !b.locked;
    servo_on_[b.first + k] = on;
    block_.joint[b.first + k] = on ? p.joint[k].cmd : shm::JointCommand{};
  }
  const int refused = ToServo(0, 0);
  refused_joints_ += refused;
  b.joint_fault = refused > 0;
  if (!started_) {
    started_ = true;
    if (!o_.quiet) std::fprintf(stderr, "hw_emulator: first command; robot time starts\n");
  }
}

// A motor board without a valid command for the hold time holds by itself: each joint whose
// servo is on holds the position it has (position mode, the model's default gains).
void Emulator::HoldIdleBoards(double now) {
  for (MotorBoard& b : motor_) {
    if (b.holding || b.last_valid < 0 || now - b.last_valid <= o_.hold_ms * 1e-3) continue;
    bool any_on = false;
    for (int k = 0; k < b.count; ++k) any_on |= servo_on_[b.first + k];
    b.holding = true;
    if (!any_on) continue;
    ++b.holds;
    block_ = wanted_;
    for (int k = 0; k < b.count; ++k) {
      const int j = b.first + k;
      if (!servo_on_[j]) continue;
      shm::JointCommand& c = block_.joint[j];
      c = shm::JointCommand{};
      c.mode = shm::JointMode::kPosition;
      c.q_ref = sensors_.q[j] + sensor_gap_->params().encoders[j].bias;  // where its encoder reads it
      c.kp = robot_.joints[j].default_kp;
      c.kd = robot_.joints[j].default_kd;
    }
    ToServo(b.first, b.count);
  }
}

void Emulator::ResetBoard(int b) {
  if (b >= static_cast<int>(motor_.size())) {  // the sensor board: its numbering starts again
    sensor_tx_seq_ = 0;
    sensor_reset_cycles_ = kSensorResetCycles;
    return;
  }
  MotorBoard& mb = motor_[b];
  block_ = wanted_;
  for (int k = 0; k < mb.count; ++k) {
    block_.joint[mb.first + k] = shm::JointCommand{};
    servo_on_[mb.first + k] = false;
  }
  ToServo(mb.first, mb.count);
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
  ToServo(0, block_.njoint);
  for (MotorBoard& b : motor_) b.locked = true;
}

// The boards' references (block_, in the encoders' frame) towards the servo: the encoders'
// bias taken out (plant_gap.h) and, with --delay-ms, through the delay ring (ApplyDelayed), but
// for joints [first, first + count), which act at once (e-stop, resets, the boards' own holds).
// A joint whose command the servo would refuse keeps its reference (counted in refused_).
// Returns the joints refused.
int Emulator::ToServo(int first, int count) {
  int refused = 0;
  servo_block_ = block_;
  sensor_gap_->ToJointFrame(q_min_.data(), q_max_.data(), &servo_block_);
  if (delay_.cycles() == 0) {
    refused = servo_->Accept(servo_block_);
    for (int i = 0; i < block_.njoint; ++i) {
      const uint32_t r = servo_->rejected_per_joint()[i];
      if (r != servo_rejected_[i]) {
        servo_rejected_[i] = r;
        ++refused_[i];
      } else {
        wanted_.joint[i] = block_.joint[i];
      }
    }
    return refused;
  }
  for (int i = 0; i < block_.njoint; ++i) {
    const model::JointMap& j = robot_.joints[i];
    if (model::CommandAcceptable(servo_block_.joint[i], j.q_min, j.q_max, j.tau_max)) {
      wanted_.joint[i] = block_.joint[i];
    } else {
      ++refused_[i];
      ++refused;
    }
  }
  if (count > 0) {  // at once: out of the ring, into the servo
    for (int j = first; j < first + count; ++j) delay_.Override(j, wanted_.joint[j]);
    servo_block_ = wanted_;
    sensor_gap_->ToJointFrame(q_min_.data(), q_max_.data(), &servo_block_);
    for (int i = 0; i < block_.njoint; ++i)
      if (i < first || i >= first + count) servo_block_.joint[i] = servo_->reference(i);
    servo_->Accept(servo_block_);
  }
  return refused;
}

// Once a cycle with --delay-ms: the references accepted that many cycles ago reach the servo.
void Emulator::ApplyDelayed() {
  servo_block_ = delay_.Shift(wanted_);
  sensor_gap_->ToJointFrame(q_min_.data(), q_max_.data(), &servo_block_);
  servo_->Accept(servo_block_);
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

// each motor board's state, then the sensor board's, stamped with the robot's time
void Emulator::SendStates(double now) {
  const uint64_t t_ns = static_cast<uint64_t>(std::llround(d_->time * 1e9));
  reported_ = sensors_;  // the readings as the robot's sensors give them: bias and noise
  sensor_gap_->Apply(robot_, &reported_);
  MotorStatePacket mp;  // one packet filled for each board in turn
  for (size_t bi = 0; bi < motor_.size(); ++bi) SendMotorState(bi, t_ns, now, &mp);
  SendSensorState(t_ns, now);
}

void Emulator::SendMotorState(size_t bi, uint64_t t_ns, double now, MotorStatePacket* packet) {
  MotorStatePacket& mp = *packet;
  MotorBoard& b = motor_[bi];
  const uint32_t seq = b.tx_seq++;
  if (faults_.silent & (1u << bi)) return;
  mp.h = Header{};
  mp.h.board = static_cast<uint8_t>(bi);
  mp.h.first = static_cast<uint8_t>(b.first);
  mp.h.count = static_cast<uint8_t>(b.count);
  mp.h.seq = seq;
  mp.h.ack = b.ack;
  mp.h.time_ns = t_ns;
  mp.h.flags = (b.reset_flag ? board_flag::kReset : 0) | (b.joint_fault ? board_flag::kJointFault : 0) |
               (b.foreign_flag > 0 ? board_flag::kForeign : 0) |
               (b.holding ? board_flag::kHolding : 0);
  if (b.foreign_flag > 0) --b.foreign_flag;
  for (int k = 0; k < b.count; ++k) {
    const int j = b.first + k;
    mp.joint[k].servo_on = servo_on_[j];
    mp.joint[k].fault = refused_[j] > 0 ? 1 : 0;
    mp.joint[k].q = j == faults_.value_joint ? faults_.value : reported_.q[j];
    mp.joint[k].dq = reported_.dq[j];
    mp.joint[k].tau = reported_.tau[j];
  }
  if (Drop()) {
    ++b.states_dropped;
    return;
  }
  const size_t n = EncodeMotorState(mp, buf_);
  Send(buf_, n, now, true);
  ++b.states_sent;
}

// the sensor board, with its stuck and saturated sensors
void Emulator::SendSensorState(uint64_t t_ns, double now) {
  const int sb = layout_.sensor_board();
  const uint32_t seq = sensor_tx_seq_++;
  if (faults_.silent & (1u << sb)) return;
  SensorStatePacket sp{};
  sp.h.board = static_cast<uint8_t>(sb);
  sp.h.count = static_cast<uint8_t>(robot_.forces.size());
  sp.h.first = static_cast<uint8_t>(robot_.imus.size());
  sp.h.ack = static_cast<uint32_t>(robot_.passive.size());  // the passive joints' encoders
  sp.h.seq = seq;
  sp.h.time_ns = t_ns;
  ReadForceSensors(&sp);
  ReadImus(&sp);
  for (uint32_t i = 0; i < sp.h.ack; ++i) {
    sp.passive_q[i] = sensors_.passive_q[i];
    sp.passive_dq[i] = sensors_.passive_dq[i];
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

// the F/T sensors (sp->h.count) as the sensor board reads them: a stuck one repeats the value
// it froze at, a saturated one is pegged at its range
void Emulator::ReadForceSensors(SensorStatePacket* sp) {
  for (int i = 0; i < sp->h.count; ++i) {
    shm::ForceTorque f = reported_.force[i];
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
    sp->force[i] = f;
  }
}

// the IMUs (sp->h.first), stuck and saturated the same way (fault bits 8 and up)
void Emulator::ReadImus(SensorStatePacket* sp) {
  for (int i = 0; i < sp->h.first; ++i) {
    const uint32_t bit = 1u << (8 + i);
    shm::Imu u = reported_.imu[i];
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
    sp->imu[i] = u;
  }
}

}  // namespace ohrp::hw::udp::emu
