// Tests the udp RobotIo's faults against fake boards on loopback: silent boards, loss /
// corruption / stale counting, loss on this machine told apart, board resets and sensor flags,
// a NaN from a board.
#include "udp_io_fixture.h"

namespace ohrp::hw::udp {
namespace {

using testing::Clock;
using testing::UdpIoTest;

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

// Every packet of the plugin carries its session id (PROTOCOL.md, "Sessions"); a board whose
// states acknowledge none of the commands sent for its timeout is named in unacked_boards (the
// board of the issue that dropped every command as stale), and no longer once it acknowledges.
TEST_F(UdpIoTest, CarriesItsSessionAndNamesABoardThatAcknowledgesNoCommand) {
  Open({"timeout_ms=2000", "timeout_ms.1=40"});
  EXPECT_NE(io_.session(), 0u);
  IoCommand c;
  ASSERT_EQ(io_.write(c), IoResult::kOk);
  CommandPacket p;
  ASSERT_TRUE(boards_.ReceiveCommand(&p));
  EXPECT_EQ(p.h.ack, io_.session());
  const auto t0 = Clock::now();
  IoState s;
  uint32_t seq = 1;
  bool named = false;
  while (!named && Clock::now() - t0 < std::chrono::seconds(5)) {
    io_.write(c);
    for (int b = 0; b < 5; ++b) boards_.SendMotor(b, seq, 0, 0, false, b == 1 ? 0 : seq);
    boards_.SendSensors(seq++);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    io_.read(&s);
    named = s.unacked_boards != 0;
  }
  ASSERT_TRUE(named);
  EXPECT_GE(Clock::now() - t0, std::chrono::milliseconds(40));
  EXPECT_EQ(s.unacked_boards, 1u << 1);
  EXPECT_TRUE(s.reports & io_report::kBoards);
  EXPECT_EQ(s.joint_board[0], 0);
  EXPECT_EQ(s.joint_board[6], 1);
  // it acknowledges the newest command: no longer named
  for (int i = 0; i < 3; ++i) {
    io_.write(c);
    for (int b = 0; b < 5; ++b) boards_.SendMotor(b, seq, 0, 0, false, seq);
    boards_.SendSensors(seq++);
  }
  ASSERT_TRUE(ReadUntil(&s, [](const IoState& x) { return x.unacked_boards == 0; }));
}

}  // namespace
}  // namespace ohrp::hw::udp
