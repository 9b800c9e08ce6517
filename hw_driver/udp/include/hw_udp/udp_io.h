// The `udp` RobotIo: hw_driver's side of the UDP protocol (hw_driver/udp/PROTOCOL.md).
// Built twice: into libohrp_io_udp.so, the plugin hw_driver loads (--io), and into a static
// library the tests link to read its counters directly.
//
// Arguments (IoConfig::args, "key=value"):
//   host=127.0.0.1        the boards' IPv4 address
//   port=7700             the boards' UDP port (board id in each packet's header)
//   bind=127.0.0.1        local address; local_port=0 (0: the system picks one)
//   timeout_ms=20         a board that sent nothing valid for this long is silent [ms]
//                         (a board that never answered since open is silent at once)
//   timeout_ms.B=N        the same for board B only
//   boards=0-5,6-12,...   motor boards' joint ranges (default: DefaultLayout of the joint names)
//   hello_every=100       cycles between hello packets to every board (0: only at open)
//   quiet=1               no summary on stderr at close
//
// open() binds the socket, connects it to the boards' address (the kernel then drops datagrams
// from any other address or port: a flood from elsewhere never reaches the queue) and sends a
// hello to every board; read() drains the socket without blocking (at most kMaxDrain
// datagrams; an empty datagram is one, counted corrupted, not the end of the queue), keeps the
// newest valid packet per board and counts lost
// (sequence gaps), corrupted (checksum, length, layout) and stale (old or duplicate) packets;
// write() sends one command packet per motor board. read and write never allocate or block.
// Every packet sent carries the session id chosen at open (PROTOCOL.md, "Sessions"); read()
// reports per board (IoState masks) a reset, a refused command, refused foreign commands, and
// commands left unacknowledged for the board's timeout_ms.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "hw_driver/robot_io.h"
#include "hw_udp/protocol.h"
#include "hw_udp/socket.h"

namespace ohrp::hw::udp {

inline constexpr int kMaxDrain = 1024;              // datagrams handled per read() at most
inline constexpr double kDefaultTimeoutMs = 20.0;   // board silence timeout [ms]
inline constexpr int kRttBins = 2000;               // round-trip histogram: 10 us bins to 20 ms
inline constexpr double kRttBinNs = 10000.0;        // [ns]

// What the plugin counted since open, per board and in total.
struct BoardStats {
  uint64_t received = 0;    // valid, new packets used
  uint64_t lost = 0;        // sequence gaps
  uint64_t stale = 0;       // old or duplicate packets dropped
  uint64_t corrupted = 0;   // checksum, length or layout mismatch (attributed by header board id)
  uint64_t silent_events = 0;  // times the board went silent
  uint64_t commands_sent = 0;
  uint8_t flags = 0;        // board_flag:: bits of its newest packet
  bool silent = true;
};

struct UdpIoStats {
  BoardStats board[kMaxBoards];
  int nboards = 0;
  uint64_t corrupted = 0;   // all undecodable datagrams (also those naming no valid board)
  uint64_t foreign = 0;     // datagrams from an unexpected address (ignored; normally 0, as the
                            // connected socket lets the kernel drop them)
  uint64_t send_failed = 0;
  uint64_t kernel_dropped = 0;  // datagrams this machine dropped (receive buffer full): they
                                // count as lost too, but the network is not to blame
  uint64_t rtt_count = 0;   // command -> state acknowledging it, measured in read()
  double rtt_sum_s = 0, rtt_max_s = 0;
  std::array<uint32_t, kRttBins + 1> rtt_hist{};  // last bin: >= 20 ms
  // the round-trip time below which a fraction `p` of the measurements lie [s]
  double RttPercentile(double p) const;
  // packets that never arrived usable: the sequence gaps of all boards, corrupted ones included
  // (a corrupted packet leaves a gap); what IoState::packets_lost says
  uint64_t lost_total() const;
};

class UdpIo final : public RobotIo {
 public:
  UdpIo() = default;
  ~UdpIo() override { close(); }

  bool open(const IoConfig& config, std::string* error) override;
  IoResult read(IoState* state) noexcept override;
  IoResult write(const IoCommand& command) noexcept override;
  void close() noexcept override;

  const UdpIoStats& stats() const { return stats_; }
  uint32_t session() const { return session_; }  // this connection's session id
  const BoardLayout& layout() const { return layout_; }
  int local_port() const { return socket_.port(); }

 private:
  struct ReadMasks;
  // read()'s stages (udp_io_read.cc)
  bool DrainSocket();
  void Handle(const uint8_t* data, size_t n, int64_t now_ns);
  void JudgeBoard(int b, int64_t now, ReadMasks* m);
  bool CopySensorBoard(IoState* state, uint64_t* time_ns) const;
  bool CopyMotorBoard(int b, IoState* state, uint64_t* time_ns) const;
  void Publish(ReadMasks* m, IoState* state);
  void SendHellos(int64_t now_ns);

  UdpSocket socket_;
  sockaddr_in boards_addr_{};
  BoardLayout layout_;
  int njoint_ = 0, nforce_ = 0, nimu_ = 0, npassive_ = 0;
  bool quiet_ = false;
  int hello_every_ = 100;
  uint64_t writes_ = 0;
  int64_t open_ns_ = 0;
  int64_t timeout_ns_[kMaxBoards] = {};
  int64_t last_rx_ns_[kMaxBoards] = {};
  SeqTracker seq_[kMaxBoards];
  uint32_t tx_seq_[kMaxBoards] = {};
  uint32_t last_ack_[kMaxBoards] = {};
  int64_t acked_ns_[kMaxBoards] = {};       // send time of the newest acknowledged command
  int64_t first_sent_ns_[kMaxBoards] = {};  // of the first command since open (-1: none yet)
  uint32_t session_ = 0;                    // chosen at open, in every packet sent
  std::array<int8_t, shm::kMaxJoints> joint_board_{};
  bool have_[kMaxBoards] = {};
  MotorStatePacket motor_[kMaxBoards];
  SensorStatePacket sensor_{};
  MotorStatePacket scratch_motor_;
  SensorStatePacket scratch_sensor_{};
  static constexpr int kSentRing = 256;
  struct Sent {
    uint32_t seq = 0;
    int64_t ns = -1;
  };
  // the references of the last kRefRing commands per board (by seq), for IoState::applied_q/dq:
  // a state acknowledging an older command than these is a board that lost contact anyway
  static constexpr int kRefRing = 64;
  struct SentRefs {
    uint32_t seq = 0;
    double q[kMaxBoardJoints] = {}, dq[kMaxBoardJoints] = {};
  };
  SentRefs sent_refs_[kMaxBoards][kRefRing] = {};
  Sent sent_[kMaxBoards][kSentRing] = {};  // send time of recent commands, for the round trip
  uint64_t lost_at_last_read_ = 0;  // gaps + corrupted at the previous read
  UdpIoStats stats_;
  uint8_t buf_[kMaxPacketSize + 64];
};

}  // namespace ohrp::hw::udp
