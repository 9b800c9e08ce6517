// The udp RobotIo (see udp_io.h and PROTOCOL.md).
#include "hw_udp/udp_io.h"
#include "shm_bridge/clock.h"

#include <time.h>

#include <random>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace ohrp::hw::udp {
namespace {

bool ParseNumber(const std::string& s, double* out) {
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == 0 && std::isfinite(*out);
}

bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

bool ParseInt(const std::string& s, long lo, long hi, long* out) {
  char* end = nullptr;
  *out = std::strtol(s.c_str(), &end, 10);
  return !s.empty() && end && *end == 0 && *out >= lo && *out <= hi;
}

}  // namespace

//---------------- statistics ----------------

double UdpIoStats::RttPercentile(double p) const {
  if (rtt_count == 0) return 0;
  const double target = p * static_cast<double>(rtt_count);
  double seen = 0;
  for (int i = 0; i <= kRttBins; ++i) {
    seen += rtt_hist[i];
    if (seen >= target) return (i + 1) * kRttBinNs * 1e-9;  // upper edge of the bin
  }
  return rtt_max_s;
}

uint64_t UdpIoStats::lost_total() const {
  uint64_t n = 0;
  for (int b = 0; b < nboards; ++b) n += board[b].lost;
  return n;
}

//---------------- set-up ----------------

bool UdpIo::open(const IoConfig& config, std::string* error) {
  close();
  std::string host = "127.0.0.1", bind_host = "127.0.0.1", boards;
  long port = kDefaultPort, local_port = 0, hello_every = 100;
  double timeout_ms = kDefaultTimeoutMs;
  std::vector<std::pair<long, double>> board_timeouts;
  quiet_ = false;
  for (const std::string& arg : config.args) {
    const size_t eq = arg.find('=');
    if (eq == std::string::npos) {
      *error = "udp io: argument '" + arg + "' is not key=value";
      return false;
    }
    const std::string key = arg.substr(0, eq), value = arg.substr(eq + 1);
    bool ok = true;
    double x = 0;
    long b = 0;
    if (key == "host") host = value;
    else if (key == "bind") bind_host = value;
    else if (key == "boards") boards = value;
    else if (key == "port") ok = ParseInt(value, 1, 65535, &port);
    else if (key == "local_port") ok = ParseInt(value, 0, 65535, &local_port);
    else if (key == "hello_every") ok = ParseInt(value, 0, 1000000000, &hello_every);
    else if (key == "quiet") quiet_ = value != "0";
    else if (key == "timeout_ms") ok = ParseNumber(value, &timeout_ms) && timeout_ms > 0;
    else if (key.rfind("timeout_ms.", 0) == 0) {
      ok = ParseInt(key.substr(11), 0, kMaxBoards - 1, &b) && ParseNumber(value, &x) && x > 0;
      board_timeouts.push_back({b, x});
    } else {
      *error = "udp io: unknown argument '" + key +
               "' (known: host, port, bind, local_port, timeout_ms, timeout_ms.B, boards, "
               "hello_every, quiet)";
      return false;
    }
    if (!ok) {
      *error = "udp io: bad value in '" + arg + "'";
      return false;
    }
  }

  // the robot and its boards
  njoint_ = static_cast<int>(config.joint_names.size());
  nforce_ = static_cast<int>(config.force_names.size());
  nimu_ = static_cast<int>(config.imu_names.size());
  npassive_ = static_cast<int>(config.passive_names.size());
  if (njoint_ < 1 || njoint_ > shm::kMaxJoints || nforce_ > shm::kMaxForceSensors ||
      nimu_ > shm::kMaxImus || npassive_ > shm::kMaxPassiveJoints) {
    *error = "udp io: the robot has " + std::to_string(njoint_) + " joints, " +
             std::to_string(nforce_) + " F/T sensors, " + std::to_string(nimu_) + " IMUs, " +
             std::to_string(npassive_) + " passive joints: outside what the protocol carries (1.." +
             std::to_string(shm::kMaxJoints) + ", " + std::to_string(shm::kMaxForceSensors) + ", " +
             std::to_string(shm::kMaxImus) + ", " + std::to_string(shm::kMaxPassiveJoints) + ")";
    return false;
  }
  if (boards.empty()) {
    layout_ = DefaultLayout(config.joint_names);
    if (layout_.nboards() > kMaxBoards) {
      *error = "udp io: the default board layout needs more than " + std::to_string(kMaxBoards) +
               " boards; give one with boards=...";
      return false;
    }
  } else if (!ParseLayout(boards, njoint_, &layout_, error)) {
    *error = "udp io: " + *error;
    return false;
  }
  for (const auto& [b, ms] : board_timeouts) {
    if (b >= layout_.nboards()) {
      *error = "udp io: timeout_ms." + std::to_string(b) + ": there are only " +
               std::to_string(layout_.nboards()) + " boards (0.." + std::to_string(layout_.nboards() - 1) + ")";
      return false;
    }
  }
  if (!MakeAddress(host, static_cast<int>(port), &boards_addr_)) {
    *error = "udp io: bad board address '" + host + "' (a dotted IPv4 address, e.g. 127.0.0.1)";
    return false;
  }
  // the socket hears the boards' address only: the kernel drops datagrams from anywhere else
  std::string why;
  if (!socket_.Open(bind_host, static_cast<int>(local_port), &why) ||
      !socket_.Connect(boards_addr_, &why)) {
    socket_.Close();
    *error = "udp io: " + why;
    return false;
  }

  // fresh counters
  hello_every_ = static_cast<int>(hello_every);
  stats_ = UdpIoStats{};
  stats_.nboards = layout_.nboards();
  for (int b = 0; b < kMaxBoards; ++b) {
    timeout_ns_[b] = static_cast<int64_t>(timeout_ms * 1e6);
    seq_[b] = SeqTracker{};
    tx_seq_[b] = 0;
    last_ack_[b] = 0;
    acked_ns_[b] = -1;
    have_[b] = false;
    last_rx_ns_[b] = 0;
    for (Sent& s : sent_[b]) s = Sent{};
    first_sent_ns_[b] = -1;
  }
  for (const auto& [b, ms] : board_timeouts) timeout_ns_[b] = static_cast<int64_t>(ms * 1e6);
  writes_ = 0;
  lost_at_last_read_ = 0;
  // this connection's session id: the boards take commands from this driver only
  std::random_device entropy;
  do {
    session_ = static_cast<uint32_t>(entropy()) ^ static_cast<uint32_t>(MonotonicNs());
  } while (session_ == 0);
  joint_board_.fill(-1);
  for (int b = 0; b < static_cast<int>(layout_.motor.size()); ++b) {
    for (int k = 0; k < layout_.motor[b].count; ++k)
      joint_board_[layout_.motor[b].first + k] = static_cast<int8_t>(b);
  }
  open_ns_ = MonotonicNs();
  SendHellos(open_ns_);
  return true;
}

void UdpIo::close() noexcept {
  if (!socket_.is_open()) return;
  socket_.Close();
  if (quiet_) return;
  const UdpIoStats& s = stats_;
  uint64_t received = 0, stale = 0, silent = 0;
  for (int b = 0; b < s.nboards; ++b) {
    received += s.board[b].received;
    stale += s.board[b].stale;
    silent += s.board[b].silent_events;
  }
  std::fprintf(stderr,
               "udp io: %d boards, received %llu, lost %llu, corrupted %llu, stale %llu, "
               "silent events %llu, send failures %llu, dropped by this machine %llu; "
               "command->state round trip p50 %.3f ms, "
               "p99 %.3f ms, max %.3f ms (%llu samples)\n",
               s.nboards, static_cast<unsigned long long>(received),
               static_cast<unsigned long long>(s.lost_total()),
               static_cast<unsigned long long>(s.corrupted), static_cast<unsigned long long>(stale),
               static_cast<unsigned long long>(silent),
               static_cast<unsigned long long>(s.send_failed),
               static_cast<unsigned long long>(s.kernel_dropped), 1e3 * s.RttPercentile(0.5),
               1e3 * s.RttPercentile(0.99), 1e3 * s.rtt_max_s,
               static_cast<unsigned long long>(s.rtt_count));
}

void UdpIo::SendHellos(int64_t now_ns) {
  for (int b = 0; b < layout_.nboards(); ++b) {
    Header h;
    h.board = static_cast<uint8_t>(b);
    h.ack = session_;
    h.time_ns = static_cast<uint64_t>(now_ns);
    const size_t n = EncodeHello(h, buf_);
    if (!socket_.SendTo(boards_addr_, buf_, n)) ++stats_.send_failed;
  }
}

//---------------- read ----------------

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
  bool socket_error = false;
  for (int i = 0; i < kMaxDrain; ++i) {
    sockaddr_in from;
    const long n = socket_.Receive(buf_, kMaxPacketSize, &from);
    if (n == kNoDatagram) break;
    if (n == kReceiveFailed) {
      socket_error = true;
      break;
    }
    // an empty datagram is one (too short: counted corrupted), not the end of the queue
    if (from.sin_addr.s_addr != boards_addr_.sin_addr.s_addr || from.sin_port != boards_addr_.sin_port) {
      ++stats_.foreign;
      continue;
    }
    Handle(buf_, static_cast<size_t>(n), MonotonicNs());
  }

  stats_.kernel_dropped = socket_.kernel_drops();

  // the newest data of every board, and who is silent
  const int64_t now = MonotonicNs();
  uint32_t faults = 0, silent = 0, nonfinite = 0, reset = 0, unacked = 0, refused = 0,
           foreign = 0;
  uint64_t time_ns = 0;
  for (int b = 0; b < layout_.nboards(); ++b) {
    BoardStats& bs = stats_.board[b];
    // a board that never answered is silent: there is nothing to read from it yet
    const bool is_silent = !have_[b] || now - last_rx_ns_[b] > timeout_ns_[b];
    if (is_silent && !bs.silent && have_[b]) ++bs.silent_events;
    bs.silent = is_silent;
    if (is_silent) silent |= 1u << b;
    if (!have_[b]) continue;
    const uint8_t f = bs.flags;
    if (f & board_flag::kReset) reset |= 1u << b;
    if (f & board_flag::kJointFault) refused |= 1u << b;
    if (f & board_flag::kForeign) foreign |= 1u << b;
    // commands unacknowledged: the newest one the board applied was sent longer ago than the
    // board's timeout (or none was, since the first command went out that long ago)
    if (b < static_cast<int>(layout_.motor.size()) && first_sent_ns_[b] >= 0 &&
        last_ack_[b] != tx_seq_[b]) {
      const int64_t since = acked_ns_[b] >= 0 ? acked_ns_[b] : first_sent_ns_[b];
      if (now - since > timeout_ns_[b]) unacked |= 1u << b;
    }
    if (f & board_flag::kReset) faults |= io_fault::kBoardReset;
    if (f & board_flag::kSensorStuck) faults |= io_fault::kSensorStuck;
    if (f & board_flag::kSensorSaturated) faults |= io_fault::kSensorSaturated;
    if (f & board_flag::kEmergencyStop) faults |= io_fault::kEmergencyStop;
    // the data, passed on as they came; a NaN or inf marks its board
    bool finite = true;
    if (b == layout_.sensor_board()) {
      time_ns = std::max(time_ns, sensor_.h.time_ns);
      for (int i = 0; i < nforce_; ++i) {
        state->force[i] = sensor_.force[i];
        finite = finite && AllFinite(sensor_.force[i].force, 3) &&
                 AllFinite(sensor_.force[i].torque, 3);
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
    } else {
      const MotorStatePacket& p = motor_[b];
      time_ns = std::max(time_ns, p.h.time_ns);
      for (int k = 0; k < p.h.count; ++k) {
        const int j = p.h.first + k;
        state->q[j] = p.joint[k].q;
        state->dq[j] = p.joint[k].dq;
        state->tau[j] = p.joint[k].tau;
        state->servo_on[j] = p.joint[k].servo_on;
        finite = finite && std::isfinite(p.joint[k].q) && std::isfinite(p.joint[k].dq) &&
                 std::isfinite(p.joint[k].tau);
      }
    }
    if (!finite) nonfinite |= 1u << b;
  }
  if (silent) faults |= io_fault::kBoardSilent;
  if (nonfinite) faults |= io_fault::kNonFinite;
  const uint64_t lost = stats_.lost_total();
  if (lost + stats_.corrupted != lost_at_last_read_) faults |= io_fault::kPacketLost;
  lost_at_last_read_ = lost + stats_.corrupted;
  state->time_ns = time_ns;
  state->faults = faults;
  state->silent_boards = silent;
  state->nonfinite_boards = nonfinite;
  state->packets_lost = lost;
  state->reports = io_report::kServoState | io_report::kFollowsCommands | io_report::kBoards;
  state->reset_boards = reset;
  state->unacked_boards = unacked;
  state->refused_boards = refused;
  state->foreign_boards = foreign;
  std::memcpy(state->joint_board, joint_board_.data(), sizeof(state->joint_board));
  if (socket_error) return IoResult::kError;
  return faults ? IoResult::kFault : IoResult::kOk;
}

//---------------- write ----------------

IoResult UdpIo::write(const IoCommand& command) noexcept {
  if (!socket_.is_open()) return IoResult::kError;
  const int64_t now = MonotonicNs();
  int failed = 0;
  CommandPacket p;
  for (int b = 0; b < static_cast<int>(layout_.motor.size()); ++b) {
    const BoardLayout::Range& r = layout_.motor[b];
    p.h = Header{};
    p.h.board = static_cast<uint8_t>(b);
    p.h.first = static_cast<uint8_t>(r.first);
    p.h.count = static_cast<uint8_t>(r.count);
    p.h.seq = ++tx_seq_[b];
    if (p.h.seq == 0) p.h.seq = ++tx_seq_[b];  // 0 means "no command yet" in acks
    p.h.ack = session_;
    p.h.time_ns = static_cast<uint64_t>(now);
    if (first_sent_ns_[b] < 0) first_sent_ns_[b] = now;
    for (int k = 0; k < r.count; ++k) {
      p.joint[k].servo_on = command.servo_on[r.first + k];
      p.joint[k].cmd = command.joint[r.first + k];
    }
    const size_t n = EncodeCommand(p, buf_);
    sent_[b][p.h.seq % kSentRing] = Sent{p.h.seq, now};
    if (socket_.SendTo(boards_addr_, buf_, n)) {
      ++stats_.board[b].commands_sent;
    } else {
      ++stats_.send_failed;
      ++failed;
    }
  }
  if (hello_every_ > 0 && ++writes_ % static_cast<uint64_t>(hello_every_) == 0) SendHellos(now);
  return failed == static_cast<int>(layout_.motor.size()) && failed > 0 ? IoResult::kError
                                                                         : IoResult::kOk;
}

}  // namespace ohrp::hw::udp
