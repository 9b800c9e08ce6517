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
    for (SentRefs& s : sent_refs_[b]) s.seq = 0;
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
    SentRefs& refs = sent_refs_[b][p.h.seq % kRefRing];
    refs.seq = p.h.seq;
    for (int k = 0; k < r.count; ++k) refs.q[k] = p.joint[k].cmd.q_ref, refs.dq[k] = p.joint[k].cmd.dq_ref;
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
