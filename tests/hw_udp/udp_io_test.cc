// Tests the udp RobotIo against fake boards played by the test on loopback: state in, commands
// out, silent boards, loss / corruption / stale counting, board resets and sensor flags, empty
// datagrams (one, or a flood from another port), a NaN from a board, and the
// plugin's exported entry loaded with dlopen.
#include <dlfcn.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <random>
#include <thread>

#include "hw_udp/protocol.h"
#include "hw_udp/socket.h"
#include "hw_udp/udp_io.h"

namespace ohrp::hw::udp {
namespace {

using Clock = std::chrono::steady_clock;
constexpr int kJoints = 29;

IoConfig Hrp1sConfig() {
  IoConfig c;
  c.robot_name = "hrp1s";
  c.joint_names = {"RLEG_HIP_R", "RLEG_HIP_P", "RLEG_HIP_Y", "RLEG_KNEE", "RLEG_ANKLE_P",
                   "RLEG_ANKLE_R", "RARM_SHOULDER_P", "RARM_SHOULDER_R", "RARM_SHOULDER_Y",
                   "RARM_ELBOW", "RARM_WRIST_Y", "RARM_WRIST_P", "RARM_WRIST_R", "LLEG_HIP_R",
                   "LLEG_HIP_P", "LLEG_HIP_Y", "LLEG_KNEE", "LLEG_ANKLE_P", "LLEG_ANKLE_R",
                   "LARM_SHOULDER_P", "LARM_SHOULDER_R", "LARM_SHOULDER_Y", "LARM_ELBOW",
                   "LARM_WRIST_Y", "LARM_WRIST_P", "LARM_WRIST_R", "WAIST_P", "WAIST_R", "CHEST"};
  c.force_names = {"rfsensor", "lfsensor", "rhsensor", "lhsensor"};
  c.imu_names = {"imu"};
  return c;
}

// The robot's boards, played in the test process on one socket.
class FakeBoards {
 public:
  FakeBoards() {
    std::string e;
    EXPECT_TRUE(socket_.Open("127.0.0.1", 0, &e)) << e;
    layout_ = DefaultLayout(Hrp1sConfig().joint_names);
  }
  int port() const { return socket_.port(); }
  const BoardLayout& layout() const { return layout_; }

  // waits for the plugin's hellos and remembers its address
  bool WaitHello() {
    const auto t0 = Clock::now();
    while (Clock::now() - t0 < std::chrono::seconds(10)) {
      if (!socket_.WaitReadable(0.1)) continue;
      uint8_t buf[kMaxPacketSize];
      sockaddr_in from;
      const long n = socket_.Receive(buf, sizeof(buf), &from);
      Header h;
      if (n > 0 && DecodeHeader(buf, n, &h) == DecodeError::kOk &&
          h.type == static_cast<uint8_t>(PacketType::kHello)) {
        peer_ = from;
        return true;
      }
    }
    return false;
  }

  // joint j reads q = j + 0.5 * `value`, dq = -j, tau = 10 j
  void SendMotor(int b, uint32_t seq, double value, uint8_t flags = 0, bool corrupt = false) {
    MotorStatePacket p;
    p.h.board = static_cast<uint8_t>(b);
    p.h.first = static_cast<uint8_t>(layout_.motor[b].first);
    p.h.count = static_cast<uint8_t>(layout_.motor[b].count);
    p.h.seq = seq;
    p.h.flags = flags;
    p.h.time_ns = 1000000ull * seq;
    for (int k = 0; k < p.h.count; ++k) {
      const int j = p.h.first + k;
      p.joint[k] = {j % 2 == 0, 0, j + 0.5 * value, -1.0 * j, 10.0 * j};
    }
    uint8_t buf[kMaxPacketSize];
    const size_t n = EncodeMotorState(p, buf);
    if (corrupt) buf[n / 2] ^= 0x04;
    ASSERT_TRUE(socket_.SendTo(peer_, buf, n));
  }

  void SendSensors(uint32_t seq, uint8_t flags = 0) {
    SensorStatePacket p{};
    p.h.board = static_cast<uint8_t>(layout_.sensor_board());
    p.h.count = 4;
    p.h.first = 1;
    p.h.seq = seq;
    p.h.flags = flags;
    for (int i = 0; i < 4; ++i) p.force[i].force[2] = 100.0 * (i + 1);
    p.imu[0].accel[2] = 9.81;
    p.imu[0].quat_WI[0] = 1;
    uint8_t buf[kMaxPacketSize];
    ASSERT_TRUE(socket_.SendTo(peer_, buf, EncodeSensorState(p, buf)));
  }

  void SendAll(uint32_t seq, double value = 0) {
    for (size_t b = 0; b < layout_.motor.size(); ++b) SendMotor(static_cast<int>(b), seq, value);
    SendSensors(seq);
  }

  // a datagram of zero bytes from the boards' own address
  void SendEmpty() {
    uint8_t none[1] = {};
    ASSERT_TRUE(socket_.SendTo(peer_, none, 0));
  }

  // receives the next command packet (skipping hellos) within `timeout`
  bool ReceiveCommand(CommandPacket* p, double timeout = 5.0) {
    const auto t0 = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - t0).count() < timeout) {
      if (!socket_.WaitReadable(0.05)) continue;
      uint8_t buf[kMaxPacketSize];
      const long n = socket_.Receive(buf, sizeof(buf), nullptr);
      if (n > 0 && DecodeCommand(buf, n, p) == DecodeError::kOk) return true;
    }
    return false;
  }

 private:
  UdpSocket socket_;
  BoardLayout layout_;
  sockaddr_in peer_{};
};

class UdpIoTest : public ::testing::Test {
 protected:
  // opens the plugin against the fake boards with extra arguments
  void Open(std::vector<std::string> extra = {}) {
    IoConfig c = Hrp1sConfig();
    c.args = {"port=" + std::to_string(boards_.port()), "quiet=1"};
    c.args.insert(c.args.end(), extra.begin(), extra.end());
    std::string e;
    ASSERT_TRUE(io_.open(c, &e)) << e;
    ASSERT_TRUE(boards_.WaitHello());
  }
  // reads until `pred` holds or 5 s pass (datagrams on loopback arrive within microseconds, but
  // a loaded machine may delay them)
  template <class Pred>
  bool ReadUntil(IoState* s, Pred pred) {
    const auto t0 = Clock::now();
    while (Clock::now() - t0 < std::chrono::seconds(5)) {
      io_.read(s);
      if (pred(*s)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return false;
  }

  FakeBoards boards_;
  UdpIo io_;
};

TEST_F(UdpIoTest, ReadsTheStateOfEveryBoard) {
  Open({"timeout_ms=5000"});
  boards_.SendAll(1, 2.0);
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) {
    return io_.stats().board[0].received && io_.stats().board[4].received && io_.stats().board[5].received;
  }));
  for (int j = 0; j < kJoints; ++j) {
    EXPECT_DOUBLE_EQ(s.q[j], j + 1.0) << j;
    EXPECT_DOUBLE_EQ(s.dq[j], -1.0 * j);
    EXPECT_DOUBLE_EQ(s.tau[j], 10.0 * j);
    EXPECT_EQ(s.servo_on[j], j % 2 == 0);
  }
  EXPECT_DOUBLE_EQ(s.force[3].force[2], 400.0);
  EXPECT_DOUBLE_EQ(s.imu[0].accel[2], 9.81);
  EXPECT_EQ(s.time_ns, 1000000u);
  EXPECT_EQ(s.faults, 0u);
  EXPECT_EQ(s.silent_boards, 0u);
  EXPECT_EQ(s.packets_lost, 0u);
}

TEST_F(UdpIoTest, WritesOneCommandPacketPerMotorBoard) {
  Open({"hello_every=0"});
  IoCommand c;
  for (int j = 0; j < kJoints; ++j) {
    c.servo_on[j] = j != 7;
    c.joint[j].mode = shm::JointMode::kPosition;
    c.joint[j].q_ref = 0.01 * j;
    c.joint[j].kp = 100 + j;
    c.joint[j].kd = 1 + j;
  }
  ASSERT_EQ(io_.write(c), IoResult::kOk);
  bool seen[5] = {};
  for (int i = 0; i < 5; ++i) {
    CommandPacket p;
    ASSERT_TRUE(boards_.ReceiveCommand(&p));
    ASSERT_LT(p.h.board, 5);
    seen[p.h.board] = true;
    EXPECT_EQ(p.h.seq, 1u);
    EXPECT_EQ(p.h.first, boards_.layout().motor[p.h.board].first);
    EXPECT_EQ(p.h.count, boards_.layout().motor[p.h.board].count);
    for (int k = 0; k < p.h.count; ++k) {
      const int j = p.h.first + k;
      EXPECT_EQ(p.joint[k].servo_on, j != 7);
      EXPECT_EQ(p.joint[k].cmd.mode, shm::JointMode::kPosition);
      EXPECT_DOUBLE_EQ(p.joint[k].cmd.q_ref, 0.01 * j);
      EXPECT_DOUBLE_EQ(p.joint[k].cmd.kp, 100.0 + j);
      EXPECT_DOUBLE_EQ(p.joint[k].cmd.kd, 1.0 + j);
    }
  }
  for (bool s : seen) EXPECT_TRUE(s);
  EXPECT_EQ(io_.stats().board[0].commands_sent, 1u);
}

TEST_F(UdpIoTest, MarksABoardSilentAfterItsOwnTimeout) {
  // board 2 times out after 50 ms; the others are given 2 s, far above any scheduling delay
  Open({"timeout_ms=2000", "timeout_ms.2=50"});
  boards_.SendAll(1);
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[2].received == 1; }));
  const auto silent_from = Clock::now();
  uint32_t seq = 2;
  bool went_silent = false;
  while (Clock::now() - silent_from < std::chrono::seconds(5)) {
    for (int b : {0, 1, 3, 4}) boards_.SendMotor(b, seq, 0);
    boards_.SendSensors(seq++);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    io_.read(&s);
    if (s.silent_boards & (1u << 2)) {
      went_silent = true;
      break;
    }
  }
  ASSERT_TRUE(went_silent);
  EXPECT_GE(Clock::now() - silent_from, std::chrono::milliseconds(50));
  EXPECT_EQ(s.silent_boards, 1u << 2);
  EXPECT_TRUE(s.faults & io_fault::kBoardSilent);
  EXPECT_EQ(io_.stats().board[2].silent_events, 1u);
  // it talks again: no longer silent
  boards_.SendMotor(2, 500, 0);
  ASSERT_TRUE(ReadUntil(&s, [](const IoState& x) { return (x.silent_boards & (1u << 2)) == 0; }));
  EXPECT_EQ(io_.stats().board[2].lost, 498u);  // its numbering went on while silent
}

TEST_F(UdpIoTest, BoardsThatNeverAnsweredAreSilentAtOnce) {
  Open({"timeout_ms=5000"});
  IoState s;
  EXPECT_EQ(io_.read(&s), IoResult::kFault);
  EXPECT_EQ(s.silent_boards, 0x3Fu);  // 5 motor boards and the sensor board
  EXPECT_TRUE(s.faults & io_fault::kBoardSilent);
  boards_.SendAll(1);
  ASSERT_TRUE(ReadUntil(&s, [](const IoState& x) { return x.silent_boards == 0; }));
  EXPECT_EQ(s.faults, 0u);
  for (int b = 0; b < 6; ++b) EXPECT_EQ(io_.stats().board[b].silent_events, 0u);
}

TEST_F(UdpIoTest, CountsInjectedLossAndCorruptionExactly) {
  Open({"timeout_ms=5000"});
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  constexpr int kPackets = 4000;
  int dropped = 0, corrupted = 0;
  IoState s;
  for (int seq = 1; seq <= kPackets; ++seq) {
    const double r = u(rng);
    const bool last = seq == kPackets;  // a loss at the very end cannot be seen
    if (r < 0.01 && !last) {
      ++dropped;
    } else if (r > 0.995 && !last) {
      ++corrupted;
      boards_.SendMotor(0, seq, 0, 0, /*corrupt=*/true);
    } else {
      boards_.SendMotor(0, seq, 0);
    }
    if (seq % 20 == 0) io_.read(&s);  // well within the socket's buffer
  }
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[0].received + corrupted + dropped == kPackets; }));
  const BoardStats& b = io_.stats().board[0];
  EXPECT_GT(dropped, 20);  // about 1 %
  EXPECT_LT(dropped, 60);
  // a corrupted packet is refused by its checksum and leaves a gap in the numbering
  EXPECT_EQ(b.lost, static_cast<uint64_t>(dropped + corrupted));
  EXPECT_EQ(io_.stats().corrupted, static_cast<uint64_t>(corrupted));
  EXPECT_EQ(s.packets_lost, static_cast<uint64_t>(dropped + corrupted));
  EXPECT_EQ(b.received, static_cast<uint64_t>(kPackets - dropped - corrupted));
  std::printf("[ figures  ] %d packets, %d dropped, %d corrupted: counted %llu gaps, %llu corrupted\n",
              kPackets, dropped, corrupted, static_cast<unsigned long long>(b.lost),
              static_cast<unsigned long long>(io_.stats().corrupted));
}

TEST_F(UdpIoTest, LossOnThisMachineIsToldApart) {
  // a flood the receive buffer cannot hold while nobody reads: the kernel drops the overflow
  Open({"timeout_ms=5000"});
  constexpr int kFlood = 5000;
  for (int seq = 1; seq <= kFlood; ++seq) boards_.SendMotor(0, seq, 0);
  IoState s;
  uint64_t received = 0;
  auto quiet_since = Clock::now();
  while (Clock::now() - quiet_since < std::chrono::milliseconds(100)) {  // drain what was kept
    io_.read(&s);
    if (io_.stats().board[0].received != received) {
      received = io_.stats().board[0].received;
      quiet_since = Clock::now();
    }
  }
  ASSERT_GT(received, 0u);
  boards_.SendMotor(0, kFlood + 1, 0);  // the next packet shows the gap
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[0].received == received + 1; }));
  const BoardStats& b = io_.stats().board[0];
  EXPECT_EQ(b.lost, io_.stats().kernel_dropped);
  EXPECT_EQ(b.lost + b.received, static_cast<uint64_t>(kFlood + 1));
  std::printf("[ figures  ] flood of %d packets: %llu dropped by the kernel, %llu gaps counted\n",
              kFlood, static_cast<unsigned long long>(io_.stats().kernel_dropped),
              static_cast<unsigned long long>(b.lost));
}

TEST_F(UdpIoTest, StaleAndDuplicatePacketsAreIgnored) {
  Open({"timeout_ms=5000"});
  boards_.SendMotor(0, 5, 2.0);
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[0].received == 1; }));
  boards_.SendMotor(0, 5, 4.0);  // duplicate number
  boards_.SendMotor(0, 3, 6.0);  // older
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[0].stale == 2; }));
  EXPECT_DOUBLE_EQ(s.q[0], 1.0);  // from seq 5's first packet
  EXPECT_EQ(io_.stats().board[0].lost, 0u);
}

TEST_F(UdpIoTest, ABoardResetIsReportedAndResynchronises) {
  Open({"timeout_ms=5000"});
  boards_.SendMotor(1, 1000, 0);
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[1].received == 1; }));
  boards_.SendMotor(1, 0, 0, board_flag::kReset);
  ASSERT_TRUE(ReadUntil(&s, [](const IoState& x) { return (x.faults & io_fault::kBoardReset) != 0; }));
  boards_.SendMotor(1, 1, 0);
  ASSERT_TRUE(ReadUntil(&s, [](const IoState& x) { return (x.faults & io_fault::kBoardReset) == 0; }));
  EXPECT_EQ(io_.stats().board[1].lost, 0u);
  EXPECT_EQ(io_.stats().board[1].received, 3u);
}

TEST_F(UdpIoTest, SensorBoardFlagsBecomeFaults) {
  Open({"timeout_ms=5000"});
  boards_.SendSensors(1, board_flag::kSensorStuck | board_flag::kSensorSaturated |
                             board_flag::kEmergencyStop);
  IoState s;
  const uint32_t want = io_fault::kSensorStuck | io_fault::kSensorSaturated | io_fault::kEmergencyStop;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState& x) { return (x.faults & want) == want; }));
}

// a NaN in a board's state is passed on, and named: io_fault::kNonFinite and the board's bit
TEST_F(UdpIoTest, ANanFromABoardNamesTheBoard) {
  Open({"timeout_ms=5000"});
  boards_.SendAll(1, 2.0);
  boards_.SendMotor(2, 2, std::nan(""));  // board 2's joints read NaN
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[2].received == 2; }));
  EXPECT_TRUE(s.faults & io_fault::kNonFinite);
  EXPECT_EQ(s.nonfinite_boards, 1u << 2);
  EXPECT_EQ(s.silent_boards, 0u);
  EXPECT_TRUE(std::isnan(s.q[boards_.layout().motor[2].first]));
  // the next good packet clears it
  boards_.SendMotor(2, 3, 2.0);
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[2].received == 3; }));
  EXPECT_FALSE(s.faults & io_fault::kNonFinite);
  EXPECT_EQ(s.nonfinite_boards, 0u);
}

TEST_F(UdpIoTest, PacketsFromElsewhereAreIgnored) {
  Open({"timeout_ms=5000"});
  UdpSocket other;
  std::string e;
  ASSERT_TRUE(other.Open("127.0.0.1", 0, &e));
  sockaddr_in plugin;
  ASSERT_TRUE(MakeAddress("127.0.0.1", io_.local_port(), &plugin));
  uint8_t junk[40] = {1, 2, 3};
  ASSERT_TRUE(other.SendTo(plugin, junk, sizeof(junk)));
  // the socket is connected to the boards: the kernel drops the junk, the boards get through
  boards_.SendAll(1, 2.0);
  IoState s;
  ASSERT_TRUE(ReadUntil(&s, [&](const IoState&) { return io_.stats().board[0].received == 1; }));
  EXPECT_EQ(io_.stats().corrupted, 0u);
  EXPECT_EQ(s.packets_lost, 0u);
}

// an empty datagram is a datagram (too short: corrupted), not "nothing waiting": the packets
// queued behind it are read in the same call
TEST_F(UdpIoTest, AnEmptyDatagramDoesNotHideThePacketsBehindIt) {
  Open({"timeout_ms=5000"});
  boards_.SendEmpty();
  boards_.SendAll(1, 2.0);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // all of them queued
  IoState s;
  io_.read(&s);
  for (int b = 0; b < boards_.layout().nboards(); ++b) {
    EXPECT_EQ(io_.stats().board[b].received, 1u) << "board " << b;
  }
  EXPECT_EQ(io_.stats().corrupted, 1u);
}

// a flood of empty datagrams from another port while the boards run: every board packet is
// read within a few cycles, none is lost
TEST_F(UdpIoTest, AFloodOfEmptyDatagramsFromAnotherPortDoesNotStallTheBoards) {
  Open({"timeout_ms=5000"});
  UdpSocket other;
  std::string e;
  ASSERT_TRUE(other.Open("127.0.0.1", 0, &e)) << e;
  sockaddr_in plugin;
  ASSERT_TRUE(MakeAddress("127.0.0.1", io_.local_port(), &plugin));
  std::atomic<bool> stop{false};
  std::atomic<long> sent{0};
  std::thread flood([&] {
    uint8_t none[1] = {};
    while (!stop.load()) {
      if (other.SendTo(plugin, none, 0)) sent.fetch_add(1);
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the flood fills the queue
  double worst = 0;
  const int nboards = boards_.layout().nboards();
  for (uint32_t seq = 1; seq <= 100; ++seq) {
    boards_.SendAll(seq, seq);
    const auto t0 = Clock::now();
    IoState s;
    const bool got = ReadUntil(&s, [&](const IoState&) {
      for (int b = 0; b < nboards; ++b) {
        if (io_.stats().board[b].received != seq) return false;
      }
      return true;
    });
    worst = std::max(worst, std::chrono::duration<double>(Clock::now() - t0).count());
    if (!got) {
      ADD_FAILURE() << "cycle " << seq << ": the boards' packets did not get through";
      break;
    }
  }
  stop.store(true);
  flood.join();
  EXPECT_GT(sent.load(), 1000) << "the flood did not run";
  EXPECT_LT(worst, 0.1) << "worst delay of a cycle's packets [s]";
  EXPECT_EQ(io_.stats().lost_total(), 0u);
}

TEST(UdpIoOpen, RefusesBadArguments) {
  UdpIo io;
  IoConfig c = Hrp1sConfig();
  std::string e;
  c.args = {"port=notaport"};
  EXPECT_FALSE(io.open(c, &e));
  EXPECT_NE(e.find("port=notaport"), std::string::npos) << e;
  c.args = {"colour=blue"};
  EXPECT_FALSE(io.open(c, &e));
  EXPECT_NE(e.find("unknown argument 'colour'"), std::string::npos) << e;
  c.args = {"boards=0-5,6-12"};
  EXPECT_FALSE(io.open(c, &e));
  EXPECT_NE(e.find("29 joints"), std::string::npos) << e;
  c.args = {"host=localhost"};
  EXPECT_FALSE(io.open(c, &e));
  EXPECT_NE(e.find("dotted IPv4"), std::string::npos) << e;
  c.args = {"timeout_ms.9=10"};
  EXPECT_FALSE(io.open(c, &e));
  EXPECT_NE(e.find("only 6 boards"), std::string::npos) << e;
  c.args = {"nokey"};
  EXPECT_FALSE(io.open(c, &e));
}

TEST(UdpIoPlugin, TheSharedObjectExportsTheEntry) {
  const std::string path = std::string(OHRP_BIN_DIR) + "/../lib/libohrp_io_udp.so";
  void* so = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(so, nullptr) << dlerror();
  using Entry = RobotIo* (*)(uint32_t);
  auto entry = reinterpret_cast<Entry>(dlsym(so, kRobotIoEntry));
  ASSERT_NE(entry, nullptr) << dlerror();
  EXPECT_EQ(entry(kRobotIoAbiVersion + 1), nullptr);
  RobotIo* io = entry(kRobotIoAbiVersion);
  ASSERT_NE(io, nullptr);
  FakeBoards boards;
  IoConfig c = Hrp1sConfig();
  c.args = {"port=" + std::to_string(boards.port()), "quiet=1", "timeout_ms=5000"};
  std::string e;
  ASSERT_TRUE(io->open(c, &e)) << e;
  ASSERT_TRUE(boards.WaitHello());
  boards.SendAll(1, 0);
  IoState s;
  const auto t0 = Clock::now();
  while (s.force[0].force[2] != 100.0 && Clock::now() - t0 < std::chrono::seconds(5)) {
    io->read(&s);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_DOUBLE_EQ(s.force[0].force[2], 100.0);
  io->close();
  delete io;
  dlclose(so);
}

}  // namespace
}  // namespace ohrp::hw::udp
