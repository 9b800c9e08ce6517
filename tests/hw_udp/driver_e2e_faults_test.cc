// The hardware chain end to end against boards that misbehave (issue 28, item 2): a forged
// datagram from another socket, implausible values from a board, a board reset under a loaded
// leg, a driver that dies. Real binaries (driver_e2e.h); each run a few seconds.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include "driver_e2e.h"
#include "hw_udp/protocol.h"

namespace ohrp::hw::udp::e2e {
namespace {

// the events named `name` in the driver's summary
std::vector<nlohmann::json> Events(const nlohmann::json& summary, const std::string& name) {
  std::vector<nlohmann::json> out;
  for (const auto& e : summary["events"])
    if (e["event"] == name) out.push_back(e);
  return out;
}

// the value of `key=` in the emulator's result line, or -1
double EmulatorResult(const std::string& out, const std::string& key) {
  const size_t line = out.rfind("hw_emulator: result ");
  if (line == std::string::npos) return -1;
  const size_t at = out.find(" " + key + "=", line);
  return at == std::string::npos ? -1 : std::atof(out.c_str() + at + key.size() + 2);
}

// The attack of the issue: one datagram from another socket to the boards' port, for board 0
// (the right leg): every servo off, sequence number +2^30. The board refuses it (it is not from
// the driver it is bound to, and the number jumps), flags it, and the driver ends in a safe mode
// with its own exit code, naming the board. Today's boards applied it, dropped every later
// command as stale, and the driver ended "completed", exit 0, the robot on the floor.
TEST_F(DriverEndToEnd, AForgedDatagramIsRefusedByTheBoardAndEndsTheRunInASafeMode) {
  auto forge = [](int port) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));  // standing by then
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    ASSERT_GE(fd, 0);
    CommandPacket p;
    p.h.board = 0;
    p.h.first = 0;
    p.h.count = 6;  // HRP-1S's right leg: joints 0-5 (DefaultLayout)
    p.h.seq = 1u << 30;
    p.h.ack = 0x5eed;  // some session: not the driver's
    for (int k = 0; k < 6; ++k) p.joint[k] = JointCommandWire{};  // servo off, mode off
    uint8_t buf[kMaxPacketSize];
    const size_t n = EncodeCommand(p, buf);
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(port));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    EXPECT_EQ(sendto(fd, buf, n, 0, reinterpret_cast<sockaddr*>(&to), sizeof(to)),
              static_cast<ssize_t>(n));
    close(fd);
  };
  const int code = RunChain({}, {"--duration", "6", "--io-arg", kBoardTimeout,
                                 "--board-timeout-cycles", kBoardCycles, "--safe-time", "0.3"},
                            0, forge);
  EXPECT_EQ(code, 8) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["outcome"], "board_disobeys");
  EXPECT_EQ(summary_["safe_mode"], true);
  const auto foreign = Events(summary_, "foreign_command");
  ASSERT_EQ(foreign.size(), 1u) << summary_["events"].dump();
  EXPECT_EQ(foreign[0]["board"], 0);
  const std::string emu = ReadFile(Path("emulator.out"));
  EXPECT_EQ(EmulatorResult(emu, "foreign"), 1) << emu;
  // the leg was never switched off by the forger: all 29 servos on until the driver's safe mode
  // ended in its servo-off (robot time: the emulator's log), and the robot stood meanwhile
  const double t_off = ServosOnUntil();
  EXPECT_GT(t_off, 2.0);
  ExpectStanding(t_off, "forged datagram refused");
  std::printf("[ figures  ] forged datagram: refused by board 0 (emulator foreign=%g), driver "
              "event at t=%.3f s, exit %d\n", EmulatorResult(emu, "foreign"),
              foreign[0]["time"].get<double>(), code);
}

// A board reads a value no joint can have for 200 ms: 1e300 rad, then NaN. Each is no valid
// read: safe mode, exit 6, and an event naming the board and the joint with the value.
TEST_F(DriverEndToEnd, ImplausibleAndNanJointValuesFor200MsEndInASafeModeNamingBoardAndJoint) {
  struct Case {
    const char* value;  // --value
    int joint, board;
  };
  for (const Case c : {Case{"2=1e300@2.0+0.2", 2, 0}, Case{"15=nan@2.0+0.2", 15, 2}}) {
    SCOPED_TRACE(c.value);
    rows_.clear();
    const int code = RunChain({"--value", c.value},
                              {"--duration", "5", "--io-arg", kBoardTimeout,
                               "--board-timeout-cycles", "50", "--safe-time", "0.2"});
    EXPECT_EQ(code, 6) << ReadFile(Path("driver.out"));
    ASSERT_FALSE(summary_.is_discarded());
    EXPECT_EQ(summary_["safe_mode"], true);
    EXPECT_EQ(summary_["outcome"], "board_fault");
    const auto bad = Events(summary_, "implausible_reading");
    ASSERT_GE(bad.size(), 1u) << summary_["events"].dump();
    EXPECT_EQ(bad[0]["board"], c.board);
    EXPECT_EQ(bad[0]["joint"], c.joint);
    EXPECT_GT(bad[0]["time"].get<double>(), 1.9);
    if (c.joint == 2) {
      EXPECT_EQ(bad[0]["reading"].get<double>(), 1e300);
    }
    if (c.joint == 15) {
      EXPECT_EQ(bad[0]["reading"], "nan");
    }
    for (const auto& e : Events(summary_, "safe_mode")) EXPECT_TRUE(e["value"] == 7 || e["value"] == 6);
    std::printf("[ figures  ] %s: event %s\n", c.value, bad[0].dump().c_str());
    fs::remove(Path("emu.csv"));
    fs::remove(Path("port"));
  }
}

// A board reset under a loaded leg (board 0, the right leg, standing): the driver re-arms the
// board and ramps its joints back while the others hold; the robot stays standing and the run
// goes on to its end, exit 0. Before: a safe mode with the reset leg limp for --safe-time; the
// leg sagged 17 deg and the robot fell, exit 0.
TEST_F(DriverEndToEnd, ABoardResetUnderALoadedLegIsHeldThroughAndTheRobotKeepsStanding) {
  const int code = RunChain({"--reset", "0@2.5"}, {"--duration", "5", "--io-arg", kBoardTimeout,
                                                    "--board-timeout-cycles", kBoardCycles});
  ASSERT_EQ(code, 0) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["outcome"], "completed");
  EXPECT_EQ(summary_["safe_mode"], false);
  EXPECT_EQ(summary_["recoveries"], 1) << summary_["events"].dump();
  std::vector<std::string> order;
  for (const auto& e : summary_["events"]) {
    const std::string name = e["event"];
    if (name == "board_reset" || name == "reset_hold" || name == "servo_on" ||
        name == "reset_ramped")
      order.push_back(name);
  }
  EXPECT_EQ(order, (std::vector<std::string>{"servo_on", "board_reset", "reset_hold", "servo_on",
                                             "reset_ramped"}))
      << summary_["events"].dump();
  // standing through the reset: the base within 2 cm of half-sitting and upright from 2 s on
  double z_lo = 1, tilt_max = 0;
  for (const Row& r : rows_) {
    if (r.t < 2.0 || r.t > ServosOnUntil()) continue;
    z_lo = std::fmin(z_lo, r.z);
    tilt_max = std::fmax(tilt_max, r.tilt);
  }
  EXPECT_NEAR(z_lo, kHalfSitHeight, 0.02);
  EXPECT_LT(tilt_max, 5.0);
  EXPECT_GT(ServosOnUntil(), 4.5);
  std::printf("[ figures  ] board reset at 2.5 s: lowest base %.4f m (half-sitting %.4f), tilt "
              "max %.2f deg through it\n", z_lo, kHalfSitHeight, tilt_max);
}

// The driver dies (SIGKILL) with the robot standing: the boards get no command any more and
// hold the joints where they are by themselves after --hold-ms; the robot keeps standing.
TEST_F(DriverEndToEnd, BoardsWithoutCommandsHoldTheRobotByThemselves) {
  auto kill_driver = [this](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(3000));
    kill(driver_, SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  };
  const int code = RunChain({}, {"--duration", "10", "--io-arg", kBoardTimeout,
                                 "--board-timeout-cycles", kBoardCycles},
                            0, kill_driver);
  EXPECT_EQ(code, 128 + SIGKILL);
  const std::string emu = ReadFile(Path("emulator.out"));
  EXPECT_GE(EmulatorResult(emu, "holds"), 5) << emu;  // the five motor boards
  ASSERT_GT(rows_.size(), 100u);
  EXPECT_NEAR(rows_.back().z, kHalfSitHeight, 0.02);
  EXPECT_LT(rows_.back().tilt, 5.0);
  EXPECT_EQ(rows_.back().on, 29);
}

// The hardware path's fall (issue 28, item 1): a push topples the emulated robot; the driver
// judges it from the measured IMU, records the fall with its time and tilt, and fails (exit 10),
// where it used to end "completed", exit 0, with the robot on the floor.
TEST_F(DriverEndToEnd, APushThatTopplesTheRobotIsAFallWithItsTimeAndTilt) {
  const int code = RunChain({"--push", "2.5,2.8,600,0,0,0,0,0"},
                            {"--duration", "6", "--io-arg", kBoardTimeout,
                             "--board-timeout-cycles", kBoardCycles, "--safe-time", "0.3"});
  EXPECT_EQ(code, 10) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["outcome"], "fall");
  const auto fall = Events(summary_, "fall");
  ASSERT_EQ(fall.size(), 1u) << summary_["events"].dump();
  EXPECT_GT(fall[0]["time"].get<double>(), 2.5);
  EXPECT_GT(fall[0]["reading"].get<double>(), 0.785);
  EXPECT_EQ(ReadFile(Path("driver.out")).find("completed after"), std::string::npos);
  // it did fall: the emulator's base tilted past the limit
  double tilt = 0;
  for (const Row& r : rows_) tilt = std::fmax(tilt, r.tilt);
  EXPECT_GT(tilt, 45.0);
  std::printf("[ figures  ] push at 2.5 s: fall event at t=%.3f s, IMU tilt %.1f deg; the "
              "emulated base tilted %.0f deg at most\n", fall[0]["time"].get<double>(),
              fall[0]["reading"].get<double>() * 180 / M_PI, tilt);
}

// The chain of the README with its defaults (issue 28, item 7): hw_driver at 1 kHz with its
// watchdog (20 cycles), board timeouts (10 cycles, timeout_ms 20), SCHED_FIFO 80 and mlockall
// where permitted, posture with its 2 s ramp. It holds the robot standing, ends exit 0, and no
// board check fires on a healthy chain. (The other tests loosen these for a loaded machine.)
TEST_F(DriverEndToEnd, TheReadmesChainWithItsDefaultsStandsTheRobot) {
#ifdef OHRP_SANITIZE
  // the README's defaults are real time at 1 kHz with a 20-cycle watchdog; built with
  // AddressSanitizer at -O1 the controller's self-collision guard (its braking check, a few
  // hundred us a cycle there) misses 20 cycles in a row and the driver drops it. The same chain
  // with loosened timing runs in the tests above.
  GTEST_SKIP() << "the README's 1 kHz timing is not met by a sanitizer build";
#endif
  readme_defaults_ = true;
  const int code = RunChain({}, {"--duration", "5"});
  ASSERT_EQ(code, 0) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["safe_mode"], false);
  ExpectStanding(ServosOnUntil(), "README chain, defaults");
  std::printf("[ figures  ] README chain at 1 kHz: %s cycles, %s deadline misses, %s late "
              "commands, wake-up p99 %s us\n", summary_["cycles"].dump().c_str(),
              summary_["deadline_misses"].dump().c_str(), summary_["late_commands"].dump().c_str(),
              summary_["lateness"]["p99_us"].dump().c_str());
}

}  // namespace
}  // namespace ohrp::hw::udp::e2e
