// Tests the UDP protocol library: packet round trips, checksum and length checks, sequence-gap
// loss counting, and the board layouts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "hw_udp/protocol.h"

namespace ohrp::hw::udp {
namespace {

std::vector<std::string> Hrp1sJoints() {
  return {"RLEG_HIP_R", "RLEG_HIP_P", "RLEG_HIP_Y", "RLEG_KNEE", "RLEG_ANKLE_P", "RLEG_ANKLE_R",
          "RARM_SHOULDER_P", "RARM_SHOULDER_R", "RARM_SHOULDER_Y", "RARM_ELBOW", "RARM_WRIST_Y",
          "RARM_WRIST_P", "RARM_WRIST_R", "LLEG_HIP_R", "LLEG_HIP_P", "LLEG_HIP_Y", "LLEG_KNEE",
          "LLEG_ANKLE_P", "LLEG_ANKLE_R", "LARM_SHOULDER_P", "LARM_SHOULDER_R", "LARM_SHOULDER_Y",
          "LARM_ELBOW", "LARM_WRIST_Y", "LARM_WRIST_P", "LARM_WRIST_R", "WAIST_P", "WAIST_R",
          "CHEST"};
}

CommandPacket SampleCommand() {
  CommandPacket p;
  p.h.board = 1;
  p.h.first = 6;
  p.h.count = 7;
  p.h.seq = 0xDEADBEEF;
  p.h.time_ns = 0x0123456789ABCDEFull;
  for (int k = 0; k < 7; ++k) {
    p.joint[k].servo_on = k % 2 == 0;
    p.joint[k].cmd.mode = static_cast<shm::JointMode>(k % 4);
    p.joint[k].cmd.q_ref = 0.1 * k - 0.25;
    p.joint[k].cmd.dq_ref = -1.0 / (k + 3);
    p.joint[k].cmd.tau_ff = 1e-300 * k;
    p.joint[k].cmd.kp = 1234.5 + k;
    p.joint[k].cmd.kd = std::numeric_limits<double>::denorm_min();
  }
  return p;
}

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* s = "123456789";
  EXPECT_EQ(Crc32(reinterpret_cast<const uint8_t*>(s), 9), 0xCBF43926u);
  EXPECT_EQ(Crc32(nullptr, 0), 0u);
}

TEST(Packets, CommandRoundTripsBitExactly) {
  const CommandPacket p = SampleCommand();
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeCommand(p, buf);
  EXPECT_EQ(n, kHeaderSize + 7 * kCommandJointSize + kCrcSize);
  // the header's fixed bytes, little-endian
  EXPECT_EQ(buf[0], 0x55);
  EXPECT_EQ(buf[1], 0x48);
  EXPECT_EQ(buf[2], kVersion);
  EXPECT_EQ(buf[3], static_cast<uint8_t>(PacketType::kCommand));
  EXPECT_EQ(buf[8], 0xEF);
  EXPECT_EQ(buf[11], 0xDE);
  CommandPacket q;
  ASSERT_EQ(DecodeCommand(buf, n, &q), DecodeError::kOk);
  EXPECT_EQ(q.h.board, 1);
  EXPECT_EQ(q.h.first, 6);
  EXPECT_EQ(q.h.count, 7);
  EXPECT_EQ(q.h.seq, 0xDEADBEEFu);
  EXPECT_EQ(q.h.time_ns, 0x0123456789ABCDEFull);
  for (int k = 0; k < 7; ++k) {
    EXPECT_EQ(q.joint[k].servo_on, p.joint[k].servo_on);
    EXPECT_EQ(q.joint[k].cmd.mode, p.joint[k].cmd.mode);
    EXPECT_EQ(std::memcmp(&q.joint[k].cmd.q_ref, &p.joint[k].cmd.q_ref, 5 * sizeof(double)), 0);
  }
}

TEST(Packets, MotorStateRoundTrips) {
  MotorStatePacket p;
  p.h.board = 4;
  p.h.first = 26;
  p.h.count = 3;
  p.h.seq = 7;
  p.h.ack = 99;
  p.h.flags = board_flag::kReset | board_flag::kJointFault;
  for (int k = 0; k < 3; ++k) p.joint[k] = {k == 1, static_cast<uint8_t>(k), 0.5 * k, -k * 2.0, 300.0 + k};
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeMotorState(p, buf);
  ASSERT_EQ(n, kHeaderSize + 3 * kStateJointSize + kCrcSize);
  MotorStatePacket q;
  ASSERT_EQ(DecodeMotorState(buf, n, &q), DecodeError::kOk);
  EXPECT_EQ(q.h.ack, 99u);
  EXPECT_EQ(q.h.flags, p.h.flags);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(q.joint[k].servo_on, k == 1);
    EXPECT_EQ(q.joint[k].fault, k);
    EXPECT_EQ(q.joint[k].q, 0.5 * k);
    EXPECT_EQ(q.joint[k].dq, -k * 2.0);
    EXPECT_EQ(q.joint[k].tau, 300.0 + k);
  }
}

TEST(Packets, SensorStateRoundTrips) {
  SensorStatePacket p{};
  p.h.board = 5;
  p.h.count = 4;
  p.h.first = 1;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) {
      p.force[i].force[k] = 100.0 * i + k;
      p.force[i].torque[k] = -(10.0 * i + k);
    }
  for (int k = 0; k < 3; ++k) {
    p.imu[0].gyro[k] = 0.01 * k;
    p.imu[0].accel[k] = k == 2 ? 9.81 : 0.0;
  }
  const double quat[4] = {0.9, 0.1, -0.2, 0.3};
  std::memcpy(p.imu[0].quat_WI, quat, sizeof(quat));
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeSensorState(p, buf);
  ASSERT_EQ(n, kHeaderSize + 4 * kForceSize + kImuSize + kCrcSize);
  SensorStatePacket q{};
  ASSERT_EQ(DecodeSensorState(buf, n, &q), DecodeError::kOk);
  EXPECT_EQ(std::memcmp(q.force, p.force, sizeof(p.force)), 0);
  EXPECT_EQ(std::memcmp(&q.imu[0], &p.imu[0], sizeof(shm::Imu)), 0);
}

// version 3: the sensor board carries the passive joints' encoders (q, dq) after the IMUs,
// their number in the header's ack field; the largest robot's state still fits a packet
TEST(Packets, SensorStateCarriesThePassiveJoints) {
  SensorStatePacket p{};
  p.h.board = 2;
  p.h.count = 2;
  p.h.first = 1;
  p.h.ack = 10;  // Cassie's ten
  for (int i = 0; i < 10; ++i) {
    p.passive_q[i] = 0.1 * i - 0.35;
    p.passive_dq[i] = -2.5 + i;
  }
  p.imu[0].quat_WI[0] = 1;
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeSensorState(p, buf);
  ASSERT_EQ(n, kHeaderSize + 2 * kForceSize + kImuSize + 10 * kPassiveSize + kCrcSize);
  SensorStatePacket q{};
  ASSERT_EQ(DecodeSensorState(buf, n, &q), DecodeError::kOk);
  EXPECT_EQ(q.h.ack, 10u);
  EXPECT_EQ(std::memcmp(q.passive_q, p.passive_q, 10 * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(q.passive_dq, p.passive_dq, 10 * sizeof(double)), 0);
  // the most the segment carries: 4 F/T, 2 IMUs, 32 passive joints
  p.h.count = shm::kMaxForceSensors;
  p.h.first = shm::kMaxImus;
  p.h.ack = shm::kMaxPassiveJoints;
  EXPECT_GT(EncodeSensorState(p, buf), 0u);
  p.h.ack = shm::kMaxPassiveJoints + 1;  // more than a sensor block holds: not encoded
  EXPECT_EQ(EncodeSensorState(p, buf), 0u);
}

TEST(Packets, EveryCorruptedByteIsDetected) {
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeCommand(SampleCommand(), buf);
  for (size_t i = 0; i < n; ++i) {
    for (uint8_t flip : {uint8_t{0x01}, uint8_t{0x80}, uint8_t{0xFF}}) {
      buf[i] ^= flip;
      Header h;
      EXPECT_NE(DecodeHeader(buf, n, &h), DecodeError::kOk) << "byte " << i;
      buf[i] ^= flip;
    }
  }
  Header h;
  EXPECT_EQ(DecodeHeader(buf, n, &h), DecodeError::kOk);
  // past the magic and version, a flipped bit is a checksum failure
  buf[20] ^= 0x10;
  EXPECT_EQ(DecodeHeader(buf, n, &h), DecodeError::kBadChecksum);
}

TEST(Packets, ShortForeignAndMislabelledPacketsAreRefused) {
  uint8_t buf[kMaxPacketSize];
  const size_t n = EncodeCommand(SampleCommand(), buf);
  Header h;
  EXPECT_EQ(DecodeHeader(buf, 10, &h), DecodeError::kTooShort);
  // a truncated packet with a valid CRC of its own: the length does not match the count
  const size_t cut = n - kCrcSize - kCommandJointSize;
  const uint32_t crc = Crc32(buf, cut);
  for (int i = 0; i < 4; ++i) buf[cut + i] = static_cast<uint8_t>(crc >> (8 * i));
  EXPECT_EQ(DecodeHeader(buf, cut + kCrcSize, &h), DecodeError::kBadLength);
  // another version
  EncodeCommand(SampleCommand(), buf);
  buf[2] = kVersion + 1;
  EXPECT_EQ(DecodeHeader(buf, n, &h), DecodeError::kBadVersion);
  buf[0] = 'X';
  EXPECT_EQ(DecodeHeader(buf, n, &h), DecodeError::kBadMagic);
  // a command is not a state
  EncodeCommand(SampleCommand(), buf);
  MotorStatePacket m;
  EXPECT_EQ(DecodeMotorState(buf, n, &m), DecodeError::kBadType);
  // counts beyond a board's capacity are not encoded
  CommandPacket big = SampleCommand();
  big.h.count = kMaxBoardJoints + 1;
  EXPECT_EQ(EncodeCommand(big, buf), 0u);
}

TEST(Packets, HelloHasNoPayload) {
  uint8_t buf[kMaxPacketSize];
  Header h;
  h.board = 3;
  const size_t n = EncodeHello(h, buf);
  EXPECT_EQ(n, kHeaderSize + kCrcSize);
  Header g;
  ASSERT_EQ(DecodeHeader(buf, n, &g), DecodeError::kOk);
  EXPECT_EQ(g.type, static_cast<uint8_t>(PacketType::kHello));
  EXPECT_EQ(g.board, 3);
}

//---------------- sequence numbers ----------------

TEST(SeqTracker, InOrderPacketsLoseNothing) {
  SeqTracker t;
  for (uint32_t s = 10; s < 1010; ++s) EXPECT_TRUE(t.Accept(s, false));
  EXPECT_EQ(t.lost(), 0u);
  EXPECT_EQ(t.received(), 1000u);
}

TEST(SeqTracker, GapsCountAsLost) {
  SeqTracker t;
  EXPECT_TRUE(t.Accept(0, false));
  EXPECT_TRUE(t.Accept(1, false));
  EXPECT_TRUE(t.Accept(5, false));   // 2, 3, 4 lost
  EXPECT_TRUE(t.Accept(6, false));
  EXPECT_TRUE(t.Accept(100, false)); // 7..99 lost
  EXPECT_EQ(t.lost(), 3u + 93u);
  EXPECT_EQ(t.received(), 5u);
}

TEST(SeqTracker, DuplicatesAndLatePacketsAreStale) {
  SeqTracker t;
  t.Accept(10, false);
  t.Accept(12, false);
  EXPECT_FALSE(t.Accept(12, false));  // duplicate
  EXPECT_FALSE(t.Accept(11, false));  // arrived after 12: counted lost already, now stale
  EXPECT_EQ(t.stale(), 2u);
  EXPECT_EQ(t.lost(), 1u);
  EXPECT_EQ(t.last(), 12u);
}

TEST(SeqTracker, WrapsAroundWithoutLoss) {
  SeqTracker t;
  t.Accept(0xFFFFFFFEu, false);
  EXPECT_TRUE(t.Accept(0xFFFFFFFFu, false));
  EXPECT_TRUE(t.Accept(0, false));
  EXPECT_TRUE(t.Accept(2, false));
  EXPECT_EQ(t.lost(), 1u);
}

TEST(SeqTracker, ARestartedSenderResynchronises) {
  SeqTracker t;
  t.Accept(5000, false);
  EXPECT_FALSE(t.Accept(0, false));  // without the reset flag: an old packet
  EXPECT_TRUE(t.Accept(0, true));    // with it: the board restarted
  EXPECT_TRUE(t.Accept(1, true));    // still flagged, in order
  EXPECT_FALSE(t.Accept(1, true));   // a duplicate stays a duplicate
  EXPECT_EQ(t.lost(), 0u);
}

// The forged datagram of issue 28: sequence +2^30. Accepted, it made the receiver drop every
// later packet of the real sender as stale; now it is refused as a jump and the sender's next
// packets go on being used.
TEST(SeqTracker, AJumpFarAheadIsRefusedAndTheSendersNextPacketsAreStillUsed) {
  SeqTracker t;
  EXPECT_TRUE(t.Accept(100, false));
  EXPECT_FALSE(t.Accept(100 + (1u << 30), false));
  EXPECT_EQ(t.jumps(), 1u);
  EXPECT_EQ(t.last(), 100u);
  EXPECT_TRUE(t.Accept(101, false));
  EXPECT_TRUE(t.Accept(102, false));
  EXPECT_EQ(t.stale(), 0u);
  // the largest gap a sender may leave is still a gap, counted lost
  EXPECT_TRUE(t.Accept(102 + kMaxSeqJump, false));
  EXPECT_EQ(t.lost(), kMaxSeqJump - 1);
  EXPECT_FALSE(t.Accept(102 + 2 * kMaxSeqJump + 1, false));
  EXPECT_EQ(t.jumps(), 2u);
  // a restarted sender (reset flag) resynchronises wherever its numbering starts
  EXPECT_TRUE(t.Accept(1u << 30, true));
}

//---------------- layout ----------------

TEST(Layout, DefaultGroupsHrp1sLimbsAndTrunk) {
  const BoardLayout l = DefaultLayout(Hrp1sJoints());
  EXPECT_EQ(LayoutString(l), "0-5,6-12,13-18,19-25,26-28");
  EXPECT_EQ(l.sensor_board(), 5);
  EXPECT_EQ(l.nboards(), 6);
}

TEST(Layout, DefaultSplitsGroupsLargerThanABoard) {
  std::vector<std::string> names;
  for (int i = 0; i < 11; ++i) names.push_back("ARM_" + std::to_string(i));
  names.push_back("HEAD");
  EXPECT_EQ(LayoutString(DefaultLayout(names)), "0-7,8-10,11-11");
}

TEST(Layout, ParsesRangesAndExplainsMistakes) {
  BoardLayout l;
  std::string e;
  ASSERT_TRUE(ParseLayout("0-5,6-12,13-18,19-25,26-28", 29, &l, &e)) << e;
  ASSERT_EQ(l.motor.size(), 5u);
  EXPECT_EQ(l.motor[1].first, 6);
  EXPECT_EQ(l.motor[1].count, 7);
  ASSERT_TRUE(ParseLayout("0,1-2", 3, &l, &e)) << e;
  EXPECT_FALSE(ParseLayout("0-5,7-12", 13, &l, &e));
  EXPECT_NE(e.find("should start at joint 6"), std::string::npos) << e;
  EXPECT_FALSE(ParseLayout("0-9", 10, &l, &e));
  EXPECT_NE(e.find("more than 8 joints"), std::string::npos) << e;
  EXPECT_FALSE(ParseLayout("0-5", 29, &l, &e));
  EXPECT_NE(e.find("robot has 29 joints"), std::string::npos) << e;
  EXPECT_FALSE(ParseLayout("0-x", 2, &l, &e));
  EXPECT_NE(e.find("not a joint range"), std::string::npos) << e;
  EXPECT_FALSE(ParseLayout("", 2, &l, &e));
}

}  // namespace
}  // namespace ohrp::hw::udp
