// Tests the udp RobotIo against datagrams that are not its boards' packets, on loopback: packets
// from elsewhere, an empty datagram, a flood of empty datagrams from another port.
#include "udp_io_fixture.h"

namespace ohrp::hw::udp {
namespace {

using testing::Clock;
using testing::UdpIoTest;

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

}  // namespace
}  // namespace ohrp::hw::udp
