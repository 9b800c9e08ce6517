// The udp RobotIo's read side (see udp_io.h and PROTOCOL.md): the socket drained into the
// boards' newest packets, then each board judged (silent, flagged, unacknowledged) and its data
// passed on, in stages; no allocation, throwing or logging.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "hw_udp/udp_io.h"
#include "shm_bridge/clock.h"

namespace ohrp::hw::udp {
namespace {

bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

}  // namespace

// what read() gathers over the boards: bit b set for board b
struct UdpIo::ReadMasks {
  uint32_t faults = 0;  // io_fault bits
  uint32_t silent = 0, nonfinite = 0, reset = 0, unacked = 0, refused = 0, foreign = 0;
  uint64_t time_ns = 0;  // the newest board time
};

void UdpIo::Handle(const uint8_t* data, size_t n, int64_t now_ns) {
  Header h;
  if (DecodeHeader(data, n, &h) != DecodeError::kOk) {
    ++stats_.corrupted;
    return;
  }
  const int b = h.board;
  if (b >= layout_.nboards()) {
    ++stats_.corrupted;
    return;
  }
  // the packet must be the board's kind and carry the board's joints or sensors
  bool ok;
  if (b == layout_.sensor_board()) {
    ok = h.count == nforce_ && h.first == nimu_ && h.ack == static_cast<uint32_t>(npassive_) &&
         DecodeSensorState(data, n, &scratch_sensor_) == DecodeError::kOk;
  } else {
    ok = h.first == layout_.motor[b].first && h.count == layout_.motor[b].count &&
         DecodeMotorState(data, n, &scratch_motor_) == DecodeError::kOk;
  }
  if (!ok) {
    ++stats_.corrupted;
    ++stats_.board[b].corrupted;
    return;
  }
  BoardStats& bs = stats_.board[b];
  const uint64_t lost_before = seq_[b].lost();
  if (!seq_[b].Accept(h.seq, (h.flags & board_flag::kReset) != 0)) {
    bs.stale = seq_[b].stale();
    return;
  }
  bs.lost += seq_[b].lost() - lost_before;
  bs.received = seq_[b].received();
  bs.flags = h.flags;
  last_rx_ns_[b] = now_ns;
  have_[b] = true;
  if (b == layout_.sensor_board()) {
    sensor_ = scratch_sensor_;
    return;
  }
  motor_[b] = scratch_motor_;
  // round trip: the first state packet acknowledging a command
  if (h.ack != 0 && h.ack != last_ack_[b]) {
    last_ack_[b] = h.ack;
    const Sent& s = sent_[b][h.ack % kSentRing];
    if (s.seq == h.ack && s.ns >= 0) acked_ns_[b] = std::max(acked_ns_[b], s.ns);
    if (s.seq == h.ack && s.ns >= 0) {
      const double rtt = 1e-9 * static_cast<double>(now_ns - s.ns);
      ++stats_.rtt_count;
      stats_.rtt_sum_s += rtt;
      stats_.rtt_max_s = std::max(stats_.rtt_max_s, rtt);
      const int bin = std::min(kRttBins, static_cast<int>(rtt * 1e9 / kRttBinNs));
      ++stats_.rtt_hist[std::max(0, bin)];
    }
  }
}

IoResult UdpIo::read(IoState* state) noexcept {
  if (!socket_.is_open()) return IoResult::kError;
  const bool socket_error = !DrainSocket();
  stats_.kernel_dropped = socket_.kernel_drops();
  // the newest data of every board, and who is silent
  ReadMasks m;
  const int64_t now = MonotonicNs();
  for (int b = 0; b < layout_.nboards(); ++b) {
    JudgeBoard(b, now, &m);
    if (!have_[b]) continue;
    const bool finite = b == layout_.sensor_board() ? CopySensorBoard(state, &m.time_ns)
                                                    : CopyMotorBoard(b, state, &m.time_ns);
    if (!finite) m.nonfinite |= 1u << b;
  }
  Publish(&m, state);
  if (socket_error) return IoResult::kError;
  return m.faults ? IoResult::kFault : IoResult::kOk;
}

// every datagram waiting (up to kMaxDrain) handled; false when the socket failed
bool UdpIo::DrainSocket() {
  for (int i = 0; i < kMaxDrain; ++i) {
    sockaddr_in from;
    const long n = socket_.Receive(buf_, kMaxPacketSize, &from);
    if (n == kNoDatagram) break;
    if (n == kReceiveFailed) return false;
    // an empty datagram is one (too short: counted corrupted), not the end of the queue
    if (from.sin_addr.s_addr != boards_addr_.sin_addr.s_addr || from.sin_port != boards_addr_.sin_port) {
      ++stats_.foreign;
      continue;
    }
    Handle(buf_, static_cast<size_t>(n), MonotonicNs());
  }
  return true;
}

// board b's health: silent, its flags, commands it has not acknowledged
void UdpIo::JudgeBoard(int b, int64_t now, ReadMasks* m) {
  BoardStats& bs = stats_.board[b];
  // a board that never answered is silent: there is nothing to read from it yet
  const bool is_silent = !have_[b] || now - last_rx_ns_[b] > timeout_ns_[b];
  if (is_silent && !bs.silent && have_[b]) ++bs.silent_events;
  bs.silent = is_silent;
  if (is_silent) m->silent |= 1u << b;
  if (!have_[b]) return;
  const uint8_t f = bs.flags;
  if (f & board_flag::kReset) m->reset |= 1u << b;
  if (f & board_flag::kJointFault) m->refused |= 1u << b;
  if (f & board_flag::kForeign) m->foreign |= 1u << b;
  // commands unacknowledged: the newest one the board applied was sent longer ago than the
  // board's timeout (or none was, since the first command went out that long ago)
  if (b < static_cast<int>(layout_.motor.size()) && first_sent_ns_[b] >= 0 &&
      last_ack_[b] != tx_seq_[b]) {
    const int64_t since = acked_ns_[b] >= 0 ? acked_ns_[b] : first_sent_ns_[b];
    if (now - since > timeout_ns_[b]) m->unacked |= 1u << b;
  }
  if (f & board_flag::kReset) m->faults |= io_fault::kBoardReset;
  if (f & board_flag::kSensorStuck) m->faults |= io_fault::kSensorStuck;
  if (f & board_flag::kSensorSaturated) m->faults |= io_fault::kSensorSaturated;
  if (f & board_flag::kEmergencyStop) m->faults |= io_fault::kEmergencyStop;
}

// the sensor board's data, passed on as they came; false when a value is NaN or inf
bool UdpIo::CopySensorBoard(IoState* state, uint64_t* time_ns) const {
  bool finite = true;
  *time_ns = std::max(*time_ns, sensor_.h.time_ns);
  for (int i = 0; i < nforce_; ++i) {
    state->force[i] = sensor_.force[i];
    finite = finite && AllFinite(sensor_.force[i].force, 3) && AllFinite(sensor_.force[i].torque, 3);
  }
  for (int i = 0; i < nimu_; ++i) {
    const shm::Imu& u = sensor_.imu[i];
    state->imu[i] = u;
    finite = finite && AllFinite(u.gyro, 3) && AllFinite(u.accel, 3) && AllFinite(u.quat_WI, 4);
  }
  for (int i = 0; i < npassive_; ++i) {
    state->passive_q[i] = sensor_.passive_q[i];
    state->passive_dq[i] = sensor_.passive_dq[i];
    finite = finite && std::isfinite(sensor_.passive_q[i]) && std::isfinite(sensor_.passive_dq[i]);
  }
  return finite;
}

// motor board b's joints, passed on as they came; false when a value is NaN or inf
bool UdpIo::CopyMotorBoard(int b, IoState* state, uint64_t* time_ns) const {
  bool finite = true;
  const MotorStatePacket& p = motor_[b];
  *time_ns = std::max(*time_ns, p.h.time_ns);
  for (int k = 0; k < p.h.count; ++k) {
    const int j = p.h.first + k;
    state->q[j] = p.joint[k].q;
    state->dq[j] = p.joint[k].dq;
    state->tau[j] = p.joint[k].tau;
    state->servo_on[j] = p.joint[k].servo_on;
    // the command this state acknowledges (the last the board applied), while it is in the ring
    const SentRefs& refs = sent_refs_[b][p.h.ack % kRefRing];
    if (p.h.ack != 0 && refs.seq == p.h.ack) state->applied_q[j] = refs.q[k], state->applied_dq[j] = refs.dq[k];
    finite = finite && std::isfinite(p.joint[k].q) && std::isfinite(p.joint[k].dq) &&
             std::isfinite(p.joint[k].tau);
  }
  return finite;
}

// the faults and the boards' masks into the state
void UdpIo::Publish(ReadMasks* m, IoState* state) {
  if (m->silent) m->faults |= io_fault::kBoardSilent;
  if (m->nonfinite) m->faults |= io_fault::kNonFinite;
  const uint64_t lost = stats_.lost_total();
  if (lost + stats_.corrupted != lost_at_last_read_) m->faults |= io_fault::kPacketLost;
  lost_at_last_read_ = lost + stats_.corrupted;
  state->time_ns = m->time_ns;
  state->faults = m->faults;
  state->silent_boards = m->silent;
  state->nonfinite_boards = m->nonfinite;
  state->packets_lost = lost;
  state->reports = io_report::kServoState | io_report::kFollowsCommands | io_report::kBoards |
                   io_report::kAppliedReferences;
  state->reset_boards = m->reset;
  state->unacked_boards = m->unacked;
  state->refused_boards = m->refused;
  state->foreign_boards = m->foreign;
  std::memcpy(state->joint_board, joint_board_.data(), sizeof(state->joint_board));
}

}  // namespace ohrp::hw::udp
