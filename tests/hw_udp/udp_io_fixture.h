// The udp RobotIo tests' fixture: HRP-1S's configuration, fake boards played by the test on
// loopback (they answer the plugin's commands with their state, and may lose, corrupt, repeat
// or delay packets), and the plugin opened on them. Used by udp_io_test.cc,
// udp_io_faults_test.cc and udp_io_datagrams_test.cc.
#pragma once

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

namespace ohrp::hw::udp::testing {

using Clock = std::chrono::steady_clock;
inline constexpr int kJoints = 29;

inline IoConfig Hrp1sConfig() {
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
  void SendMotor(int b, uint32_t seq, double value, uint8_t flags = 0, bool corrupt = false,
                 uint32_t ack = 0) {
    MotorStatePacket p;
    p.h.ack = ack;
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

}  // namespace ohrp::hw::udp::testing
