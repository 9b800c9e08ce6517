// The built `balance` program, unchanged, on the hardware path: hw_emulator (the boards, a
// MuJoCo HRP-1S behind them, real time) <- UDP -> hw_driver with libohrp_io_udp.so (2 ms servo
// cycle, real-time pacing) <- segment -> balance. The emulator's log says whether the robot
// stands; faults injected in the emulator (a stuck F/T sensor, a silent board) reach balance as
// the driver's kBoardFault status. Skipped when the hardware programs are not built. Bounds are
// generous in wall time: the machine may be loaded.
#include <signal.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "fake_robot.h"
#include "shm_bridge/bridge.h"

namespace ohrp::controllers::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr double kHalfSitHeight = 0.6839;  // base height of the halfsit keyframe [m]
constexpr double kWall = 120.0;            // [s] no wait is longer

struct Row {
  double t, z, tilt;  // robot time [s], base height [m], tilt [deg]
  int on;             // servos on
};

struct Chain {
  int driver = -1, balance = -1, emulator = -1;  // exit codes
  std::string balance_out, driver_out;
  std::vector<Row> rows;
  nlohmann::json summary;
};

// Runs emulator (halfsit keyframe, `emulator_args`), driver (`duration` s of servo cycles),
// then balance; the emulator is stopped with SIGINT once the driver ended.
Chain RunChain(const std::string& tag, std::vector<std::string> emulator_args, double duration) {
  Chain c;
  const std::string base = TempPath(tag);
  const fs::path dir = base + "_dir";
  fs::remove(base);
  fs::create_directories(dir);
  auto path = [&](const char* f) { return (dir / f).string(); };
  std::vector<std::string> e = {Program("hw_emulator"), "--model", kScene, "--keyframe",
                                "halfsit", "--port", "0", "--port-file", path("port"),
                                "--wait-driver", "60", "--log", path("emu.csv"), "--log-every",
                                "10"};
  e.insert(e.end(), emulator_args.begin(), emulator_args.end());
  const pid_t emulator = Spawn(e, path("emu.out"));
  int port = 0;
  for (double t = 0; port == 0 && t < kWall; t += 0.01) {
    std::ifstream in(path("port"));
    if (!(in >> port)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_NE(port, 0) << ReadText(path("emu.out"));
  const std::string segment = UniqueSegment(tag);
  const pid_t driver = Spawn(
      {Program("hw_driver"), "--model", kScene, "--io", Program("../lib/libohrp_io_udp.so"),
       "--io-arg", "port=" + std::to_string(port), "--io-arg", "timeout_ms=100", "--segment",
       segment, "--period", "0.002", "--watchdog-cycles", "100", "--board-timeout-cycles",
       "100", "--rt-priority", "0", "--no-mlock", "--duration", std::to_string(duration),
       "--summary", path("driver.json")},
      path("driver.out"));
  const std::string shm_path = "/dev/shm/" + shm::SegmentObjectName(segment);
  for (double t = 0; !fs::exists(shm_path) && t < kWall; t += 0.01)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  const pid_t balance = Spawn({Program("balance"), "--segment", segment}, path("balance.out"));
  c.driver = WaitExit(driver, kWall);
  c.balance = WaitExit(balance, kWall);
  kill(emulator, SIGINT);
  c.emulator = WaitExit(emulator, kWall);
  c.balance_out = ReadText(path("balance.out"));
  c.driver_out = ReadText(path("driver.out"));
  std::ifstream log(path("emu.csv"));
  std::string line;
  std::getline(log, line);
  while (std::getline(log, line)) {
    Row r{};
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%d", &r.t, &r.z, &r.tilt, &r.on) == 4)
      c.rows.push_back(r);
  }
  c.summary = nlohmann::json::parse(ReadText(path("driver.json")), nullptr, false);
  fs::remove_all(dir);
  RemoveSegment(segment);
  return c;
}

// base height and tilt over [t0, t1] of robot time, servos on: {z_lo, z_hi, tilt_max}
std::array<double, 3> Span(const Chain& c, double t0, double t1) {
  std::array<double, 3> s = {1e9, -1e9, 0};
  int n = 0;
  for (const Row& r : c.rows) {
    if (r.t < t0 || r.t > t1 || r.on != 29) continue;
    ++n;
    s[0] = std::min(s[0], r.z);
    s[1] = std::max(s[1], r.z);
    s[2] = std::max(s[2], r.tilt);
  }
  EXPECT_GT(n, 20) << "emulator log rows in [" << t0 << ", " << t1 << "] s";
  return s;
}

// the producer time balance reports holding from, -1 when it did not hold
double HoldTime(const std::string& out) {
  const std::string key = "HELD the last commanded posture from t = ";
  const std::size_t at = out.find(key);
  return at == std::string::npos ? -1.0 : std::atof(out.c_str() + at + key.size());
}

class BalanceHw : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* p : {"hw_driver", "hw_emulator", "balance", "../lib/libohrp_io_udp.so"})
      if (!fs::exists(Program(p))) GTEST_SKIP() << Program(p) << " is not built";
  }
};

// 2. the program that stands on sim_host stands the emulated robot through the driver
TEST_F(BalanceHw, StandsThroughHwDriverAndUdp) {
  const Chain c = RunChain("bal_hw", {}, 7.0);
  ASSERT_EQ(c.driver, 0) << c.driver_out;
  ASSERT_EQ(c.balance, 0) << c.balance_out;
  EXPECT_EQ(c.emulator, 130);
  EXPECT_NE(c.balance_out.find("balance: stood"), std::string::npos) << c.balance_out;
  EXPECT_EQ(c.balance_out.find("HELD"), std::string::npos) << c.balance_out;
  ASSERT_FALSE(c.summary.is_discarded());
  EXPECT_EQ(c.summary["safe_mode"], false);
  EXPECT_EQ(c.summary["rejected_commands"], 0);
  // standing (ramp, settle, centring done by 3.5 s): within 2 cm of the keyframe's height,
  // 3 mm of spread, upright within 3 degrees, until the driver's end (7 s)
  const auto s = Span(c, 3.5, 6.9);
  EXPECT_NEAR(s[0], kHalfSitHeight, 0.02);
  EXPECT_LT(s[1] - s[0], 0.003);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] balance on hw_driver + udp + hw_emulator: base z %.4f..%.4f m, tilt "
              "max %.2f deg in [3.5, 6.9] s; driver: %s late commands, %s deadline misses\n%s",
              s[0], s[1], s[2], c.summary["late_commands"].dump().c_str(),
              c.summary["deadline_misses"].dump().c_str(), c.balance_out.c_str());
}

// 5. a stuck ankle F/T sensor (stale values): the driver flags kBoardFault, balance holds its
// last posture from then on and says so; the held robot keeps standing
TEST_F(BalanceHw, AStuckAnkleSensorLatchesTheHold) {
  const Chain c = RunChain("bal_hw_stuck", {"--stuck", "ft0@4.5"}, 6.5);
  ASSERT_EQ(c.driver, 0) << c.driver_out;
  ASSERT_EQ(c.balance, 0) << c.balance_out;
  // (driver time, which starts a few cycles before the emulator's robot time)
  EXPECT_GE(HoldTime(c.balance_out), 4.5) << c.balance_out;
  EXPECT_LT(HoldTime(c.balance_out), 4.7) << c.balance_out;
  EXPECT_NE(c.balance_out.find("board fault reported by the producer"), std::string::npos)
      << c.balance_out;
  EXPECT_EQ(c.summary["rejected_commands"], 0);
  const auto s = Span(c, 4.6, 6.4);
  EXPECT_NEAR(s[0], kHalfSitHeight, 0.02);
  EXPECT_LT(s[1] - s[0], 0.003);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] stuck ft0 at 4.5 s: base z %.4f..%.4f m, tilt max %.2f deg after\n%s",
              s[0], s[1], s[2], c.balance_out.c_str());
}

// a board falling silent: the driver's safe mode ends the run (exit 6); balance held from the
// silence on (kBoardFault, never NaN: the driver rejected no command)
TEST_F(BalanceHw, ASilentBoardLatchesTheHoldBeforeTheDriversSafeMode) {
  const Chain c = RunChain("bal_hw_silent", {"--silent", "2@4.5"}, 7.0);
  ASSERT_EQ(c.driver, 6) << c.driver_out;
  // the plugin marks the board silent after timeout_ms (100 ms): until then the driver
  // publishes the board's last values (stale), which balance cannot tell from fresh ones
  EXPECT_GE(HoldTime(c.balance_out), 4.6) << c.balance_out;
  EXPECT_LT(HoldTime(c.balance_out), 4.8) << c.balance_out;
  EXPECT_EQ(c.balance, 6) << "balance's exit code when the producer ends in failure";
  EXPECT_NE(c.balance_out.find("board fault reported by the producer"), std::string::npos)
      << c.balance_out;
  EXPECT_EQ(c.summary["rejected_commands"], 0);
  std::printf("[ figures  ] silent board 2 at 4.5 s: driver exit %d, balance exit %d\n%s",
              c.driver, c.balance, c.balance_out.c_str());
}

}  // namespace
}  // namespace ohrp::controllers::testing
