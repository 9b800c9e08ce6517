// Tests the udp RobotIo against fake boards played by the test on loopback (udp_io_fixture.h):
// state in, commands out, bad arguments refused, and the plugin's exported entry loaded with
// dlopen. Silent boards and bad packets are tested in udp_io_faults_test.cc, foreign and empty
// datagrams in udp_io_datagrams_test.cc.
#include <dlfcn.h>

#include "udp_io_fixture.h"

namespace ohrp::hw::udp {
namespace {

using testing::Clock;
using testing::FakeBoards;
using testing::Hrp1sConfig;
using testing::kJoints;
using testing::UdpIoTest;

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
