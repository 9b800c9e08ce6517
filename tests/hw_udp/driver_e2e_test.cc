// Tests the whole hardware chain end to end with the real binaries: hw_emulator (the boards, a
// MuJoCo HRP-1S behind them) <- UDP -> hw_driver with libohrp_io_udp.so <- segment -> posture.
// posture ramps the robot to half-sitting; the emulator's log says whether it stands.
// Skipped when hw_driver or posture is not built. Bounds are generous: the machine may be loaded.
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/process.h"
#include "runner/checks.h"  // runner::Table: the data logs' reader
#include "common/scratch.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw::udp {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kBin = OHRP_BIN_DIR;
const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr double kHalfSitHeight = 0.6839;  // base height of the half-sitting keyframe [m]
constexpr double kMaxWall = 90.0;          // [s] no wait in this test is longer

double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// starts `args`, its stdout and stderr into the file `out`
pid_t Exec(const std::vector<std::string>& args, const std::string& out) {
  return ohrp::testing::Spawn(args, ohrp::testing::ToFile(out));
}

// exit code once `*pid` ended within `timeout`, else -1
using ohrp::testing::WaitExit;

using ohrp::testing::ReadFile;

// the board timeouts of the runs that must end clean: a board silent for 1 s (a stall of the
// loaded VM is shorter) is a fault; the silent-board test times its own shorter ones
constexpr const char* kBoardTimeout = "timeout_ms=1000";
constexpr const char* kBoardCycles = "500";

class DriverEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    for (const char* p : {"/hw_driver", "/posture", "/hw_emulator"})
      if (!fs::exists(kBin + p)) GTEST_SKIP() << kBin << p << " is not built";
    segment_ = "udpe2e_" + std::to_string(getpid());
    dir_ = ohrp::testing::ScratchFolder("e2e");
    fs::remove(ShmPath());
  }
  void TearDown() override {
    for (pid_t* p : {&posture_, &driver_, &emulator_}) ohrp::testing::Kill(p);
    fs::remove(ShmPath());
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  std::string ShmPath() const { return "/dev/shm/" + shm::SegmentObjectName(segment_); }
  std::string Path(const char* f) const { return (dir_ / f).string(); }

  // Runs the chain: hw_emulator with `emulator_args`, hw_driver (udp plugin, `driver_args`, a
  // controller watchdog of 1 s so that a loaded machine does not trip the safe mode), then posture
  // ramping to half-sitting in 1 s. Returns hw_driver's exit code; the emulator is stopped with
  // SIGINT afterwards and its log read into rows_. `sigint_after` > 0: hw_driver gets a SIGINT
  // that many wall seconds after posture started (a stop by hand).
  int RunChain(std::vector<std::string> emulator_args, std::vector<std::string> driver_args,
               double sigint_after = 0) {
    std::vector<std::string> e = {kBin + "/hw_emulator", "--model", kScene, "--port", "0",
                                  "--port-file", Path("port"), "--wait-driver", "60", "--log",
                                  Path("emu.csv"), "--log-every", "10"};
    e.insert(e.end(), emulator_args.begin(), emulator_args.end());
    emulator_ = Exec(e, Path("emulator.out"));
    int port = 0;
    for (auto t0 = Clock::now(); port == 0 && Since(t0) < kMaxWall;) {
      std::ifstream in(Path("port"));
      if (!(in >> port)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
      if (WaitExit(&emulator_, 0) != -1) {
        ADD_FAILURE() << ReadFile(Path("emulator.out"));
        return -1;
      }
    }
    if (port == 0) return -1;

    std::vector<std::string> d = {
        kBin + "/hw_driver", "--model", kScene, "--io", kBin + "/../lib/libohrp_io_udp.so",
        "--io-arg", "port=" + std::to_string(port), "--segment", segment_, "--period", "0.002",
        "--watchdog-cycles", "500", "--rt-priority", "0", "--no-mlock", "--summary",
        Path("driver.json")};
    d.insert(d.end(), driver_args.begin(), driver_args.end());
    driver_ = Exec(d, Path("driver.out"));
    bool segment = false;
    for (auto t0 = Clock::now(); !segment && Since(t0) < kMaxWall;) {
      std::error_code ec;
      segment = fs::file_size(ShmPath(), ec) == sizeof(shm::Segment) && !ec;
      if (!segment) {
        if (WaitExit(&driver_, 0) != -1) {
          ADD_FAILURE() << ReadFile(Path("driver.out"));
          return -1;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
    if (!segment) return -1;

    // the controller, as against sim_host
    posture_ = Exec({kBin + "/posture", "--segment", segment_, "--ramp", "1.0"}, Path("posture.out"));
    if (sigint_after > 0 && WaitExit(&driver_, sigint_after) == -1) kill(driver_, SIGINT);
    const int code = WaitExit(&driver_, kMaxWall);
    WaitExit(&posture_, kMaxWall);
    kill(emulator_, SIGINT);
    EXPECT_EQ(WaitExit(&emulator_, kMaxWall), 130) << ReadFile(Path("emulator.out"));

    // the emulator's log: time, base_z, tilt_deg, servos_on, ...
    std::ifstream log(Path("emu.csv"));
    std::string line;
    std::getline(log, line);
    while (std::getline(log, line)) {
      Row r{};
      if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%d", &r.t, &r.z, &r.tilt, &r.on) == 4)
        rows_.push_back(r);
    }
    summary_ = nlohmann::json::parse(ReadFile(Path("driver.json")), nullptr, false);
    return code;
  }

  // the robot stood half-sitting, upright, in the second before `t_end` - 0.3 s (robot time)
  void ExpectStanding(double t_end, const char* what) {
    int checked = 0;
    double z_lo = 1, z_hi = 0, tilt_max = 0;
    for (const Row& r : rows_) {
      if (r.t < t_end - 1.2 || r.t > t_end - 0.3) continue;
      ++checked;
      z_lo = std::fmin(z_lo, r.z);
      z_hi = std::fmax(z_hi, r.z);
      tilt_max = std::fmax(tilt_max, r.tilt);
    }
    ASSERT_GT(checked, 50);
    EXPECT_NEAR(z_lo, kHalfSitHeight, 0.02);
    EXPECT_NEAR(z_hi, kHalfSitHeight, 0.02);
    EXPECT_LT(tilt_max, 5.0);
    std::printf("[ figures  ] %s: base z %.4f..%.4f m (half-sitting %.4f), tilt max %.2f deg in "
                "[%.2f, %.2f] s of robot time\n",
                what, z_lo, z_hi, kHalfSitHeight, tilt_max, t_end - 1.2, t_end - 0.3);
  }
  // the last robot time at which all 29 servos were on
  double ServosOnUntil() const {
    double t = 0;
    for (const Row& r : rows_)
      if (r.on == 29) t = r.t;
    return t;
  }

  struct Row {
    double t, z, tilt;
    int on;
  };
  std::vector<Row> rows_;
  nlohmann::json summary_;
  std::string segment_;
  fs::path dir_;
  pid_t emulator_ = -1, driver_ = -1, posture_ = -1;
};

// sim_host's data log of the robot standing half-sitting (posture, 4 s lock-step)
void RunSimHost(const std::string& segment, const std::string& log, const std::string& out) {
  pid_t sim = Exec({kBin + "/sim_host", "--scene", kScene, "--segment", segment, "--duration",
                    "4", "--log", log, "--progress", "0"},
                   out + ".sim");
  bool segment_up = false;
  const std::string shm = "/dev/shm/" + shm::SegmentObjectName(segment);
  for (auto t0 = Clock::now(); !segment_up && Since(t0) < kMaxWall;) {
    segment_up = fs::exists(shm);
    if (!segment_up) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(segment_up) << ReadFile(out + ".sim");
  pid_t posture = Exec({kBin + "/posture", "--segment", segment, "--ramp", "1.0"}, out + ".posture");
  ASSERT_EQ(WaitExit(&sim, kMaxWall), 0) << ReadFile(out + ".sim");
  ASSERT_EQ(WaitExit(&posture, kMaxWall), 0) << ReadFile(out + ".posture");
}

// FNV-1a (64 bit) of a file's bytes: the identity of a program file
uint64_t FileHash(const std::string& path) {
  const std::string bytes = ReadFile(path);
  return shm::Fnv1a64(bytes.data(), bytes.size());
}

// The paper's claim (section 3.1): the binary developed on the simulator runs on the robot as
// is. The same posture file, byte for byte, stands the robot on sim_host and, through
// hw_driver and the udp plugin, on the emulated boards.
TEST_F(DriverEndToEnd, TheSamePostureFileStandsTheRobotOnSimHostAndOnTheDriver) {
  const std::string posture = kBin + "/posture";
  const uint64_t hash_before = FileHash(posture);
  ASSERT_GT(ReadFile(posture).size(), 1000u);

  // 1. against sim_host (lock-step), its own log says where the base is
  const std::string sim_log = Path("sim.csv");
  pid_t sim = Exec({kBin + "/sim_host", "--scene", kScene, "--segment", segment_, "--duration",
                    "4", "--log", sim_log, "--progress", "0"},
                   Path("sim.out"));
  bool segment = false;
  for (auto t0 = Clock::now(); !segment && Since(t0) < kMaxWall;) {
    segment = fs::exists(ShmPath());
    if (!segment) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(segment) << ReadFile(Path("sim.out"));
  posture_ = Exec({posture, "--segment", segment_, "--ramp", "1.0"}, Path("posture_sim.out"));
  ASSERT_EQ(WaitExit(&sim, kMaxWall), 0) << ReadFile(Path("sim.out"));
  ASSERT_EQ(WaitExit(&posture_, kMaxWall), 0) << ReadFile(Path("posture_sim.out"));
  std::ifstream log(sim_log);
  std::string header, line, last;
  std::getline(log, header);
  while (std::getline(log, line)) last = line;
  double t = 0, x = 0, y = 0, z = 0;
  ASSERT_EQ(std::sscanf(last.c_str(), "%lf,%lf,%lf,%lf", &t, &x, &y, &z), 4);
  EXPECT_NEAR(z, kHalfSitHeight, 0.02) << "on sim_host";

  // 2. the same file against hw_driver + udp + hw_emulator
  ASSERT_EQ(RunChain({}, {"--duration", "5", "--io-arg", kBoardTimeout,
                          "--board-timeout-cycles", kBoardCycles}),
            0)
      << ReadFile(Path("driver.out"));
  ExpectStanding(ServosOnUntil(), "same posture file on the driver");

  // 3. it was the same program both times
  EXPECT_EQ(FileHash(posture), hash_before);
  std::printf("[ figures  ] posture file hash %016llx: sim_host base z %.4f m, driver chain above\n",
              static_cast<unsigned long long>(hash_before), z);
}

TEST_F(DriverEndToEnd, PostureThroughHwDriverAndUdpKeepsTheEmulatedRobotStanding) {
  ASSERT_EQ(RunChain({}, {"--duration", "5", "--io-arg", kBoardTimeout,
                          "--board-timeout-cycles", kBoardCycles}),
            0)
      << ReadFile(Path("driver.out"));
  ASSERT_GT(rows_.size(), 100u);
  const double t_off = ServosOnUntil();  // the driver's servo-off at its end
  ASSERT_GT(t_off, 3.0) << "servos on for too short a time";
  ExpectStanding(t_off, "end to end");
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["packets_lost"], 0);
  EXPECT_EQ(summary_["safe_mode"], false);
  std::printf("%s", ReadFile(Path("driver.out")).c_str());
}

TEST_F(DriverEndToEnd, OnePercentLossIsSurvivedAndCounted) {
  ASSERT_EQ(RunChain({"--loss", "0.01", "--seed", "3"},
                     {"--duration", "4", "--io-arg", kBoardTimeout,
                      "--board-timeout-cycles", kBoardCycles}),
            0)
      << ReadFile(Path("driver.out"));
  ExpectStanding(ServosOnUntil(), "1% loss");
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["safe_mode"], false);
  // 6 boards x ~1 kHz x ~4 s, 1 % lost
  const double lost = summary_["packets_lost"].get<double>();
  EXPECT_GT(lost, 100);
  EXPECT_LT(lost, 600);
  std::printf("[ figures  ] 1%% loss end to end: the driver counted %.0f packets lost\n", lost);
}

TEST_F(DriverEndToEnd, ASilentBoardTripsTheDriversSafeMode) {
  // board 2 (left leg) falls silent at robot time 3 s; the plugin marks it after 100 ms, the
  // driver enters safe mode after 50 cycles of silence (100 ms) and ends with exit 6
  const int code = RunChain({"--silent", "2@3.0"},
                            {"--duration", "6", "--io-arg", "timeout_ms=100",
                             "--board-timeout-cycles", "50"});
  ASSERT_EQ(code, 6) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["safe_mode"], true);
  EXPECT_EQ(summary_["outcome"], "board_fault");
  // the robot was standing before the board fell silent
  ExpectStanding(3.0, "before the silent board");
  // the safe mode came after the silence began, within a few timeouts (driver time, which
  // starts a few cycles before the emulator's robot time)
  double silent_at = -1, safe_at = -1;
  for (const auto& e : summary_["events"]) {
    // (all boards are "silent" at cycle 0, before their first answer: mask 0x3f)
    if (e["event"] == "board_silent" && e["value"] == 4 && silent_at < 0)
      silent_at = e["time"].get<double>();
    if (e["event"] == "safe_mode" && safe_at < 0) safe_at = e["time"].get<double>();
  }
  EXPECT_GT(silent_at, 2.9) << summary_["events"].dump();
  EXPECT_GE(safe_at, silent_at) << summary_["events"].dump();
  EXPECT_LT(safe_at, 4.0) << summary_["events"].dump();
  std::printf("[ figures  ] silent board at robot time 3.0 s: marked silent at %.3f s, the "
              "driver's safe mode at %.3f s (driver time)\n", silent_at, safe_at);
}

TEST_F(DriverEndToEnd, ABoardResetIsReArmedAndTheServosComeOnAgain) {
  // board 0 restarts at robot time 2 s: its servos are off until an all-off command re-arms it;
  // the driver's safe mode ends in that servo-off, then the servos come on again
  const int code = RunChain({"--reset", "0@2.0"}, {"--duration", "5", "--safe-time", "0.2",
                                                    "--io-arg", kBoardTimeout,
                                                    "--board-timeout-cycles", kBoardCycles});
  ASSERT_EQ(code, 0) << ReadFile(Path("driver.out"));
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["outcome"], "completed");
  EXPECT_EQ(summary_["recoveries"], 1) << summary_["events"].dump();
  std::vector<std::string> order;
  for (const auto& e : summary_["events"]) {
    const std::string name = e["event"];
    if (name == "board_reset" || name == "board_rearm" || name == "servo_on") order.push_back(name);
  }
  EXPECT_EQ(order, (std::vector<std::string>{"servo_on", "board_reset", "board_rearm", "servo_on"}))
      << summary_["events"].dump();
  EXPECT_GT(ServosOnUntil(), 4.0);  // all 29 servos on again on the emulated robot
}

// hw_driver --log writes sim_host's data log format: the same column names but the simulator's
// ground truth (base_*), read by the same reader (runner::Table), one row per servo cycle, a
// period apart; and the values are the robot's: standing half-sitting, the joints where
// sim_host's robot has them and the feet carrying the same weight.
TEST_F(DriverEndToEnd, TheDriversLogHasSimHostsColumnsAndTheSameReaderReadsIt) {
  RunSimHost(segment_ + "s", Path("sim.csv"), Path("sim"));
  runner::Table sim, drv;
  std::string error;
  ASSERT_TRUE(sim.Load(Path("sim.csv"), &error)) << error;
  ASSERT_EQ(RunChain({}, {"--duration", "4", "--io-arg", kBoardTimeout,
                          "--board-timeout-cycles", kBoardCycles, "--log", Path("driver.csv")}),
            0)
      << ReadFile(Path("driver.out"));
  ASSERT_TRUE(drv.Load(Path("driver.csv"), &error)) << error;

  // the columns: sim_host's, less the ground truth
  std::vector<std::string> expected;
  for (const auto& n : sim.names())
    if (n.rfind("base_", 0) != 0) expected.push_back(n);
  EXPECT_EQ(drv.names(), expected);
  EXPECT_EQ(sim.names().size(), expected.size() + 10);  // base x y z, quaternion, velocity
  EXPECT_EQ(drv.Column("base_z"), -1);

  // one row per servo cycle (the summary's count), a period apart, times strictly increasing
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(drv.rows(), summary_["cycles"].get<size_t>());
  const auto& t = drv.col(drv.Column("time"));
  double dt_min = 1, dt_max = 0;
  for (size_t i = 1; i < t.size(); ++i) {
    dt_min = std::fmin(dt_min, t[i] - t[i - 1]);
    dt_max = std::fmax(dt_max, t[i] - t[i - 1]);
  }
  EXPECT_NEAR(dt_min, 0.002, 1e-9);  // skipped slots (a loaded machine) make larger steps only
  // the last row is the last cycle run: the duration, then the stop's damped hold before the
  // servo-off (--servo-off-time, 0.2 s by default)
  EXPECT_NEAR(t.back(), summary_["duration"].get<double>(), 1e-6);
  EXPECT_NEAR(t.back(), 4.0 + 0.2, 0.01);

  // the values: the last row of each log, the robot standing half-sitting on both
  auto last = [](const runner::Table& tb, const std::string& name) {
    const int c = tb.Column(name);
    EXPECT_GE(c, 0) << name;
    return c < 0 ? NAN : tb.col(c).back();
  };
  double worst_q = 0;
  for (const auto& n : expected) {
    if (n.rfind("q_", 0) != 0) continue;
    worst_q = std::fmax(worst_q, std::fabs(last(drv, n) - last(sim, n)));
  }
  EXPECT_LT(worst_q, 0.02);
  const double fz_sim = last(sim, "rfsensor_fz") + last(sim, "lfsensor_fz");
  const double fz_drv = last(drv, "rfsensor_fz") + last(drv, "lfsensor_fz");
  EXPECT_GT(fz_sim, 100.0);
  EXPECT_NEAR(fz_drv, fz_sim, 0.05 * fz_sim);
  std::printf("[ figures  ] driver log: %zu columns (sim_host's %zu less 10 base_*), %zu rows = "
              "cycles, dt %.6f..%.6f s; last row: joints within %.4f rad of sim_host's, feet "
              "%.1f N (sim_host %.1f N)\n",
              drv.names().size(), sim.names().size(), drv.rows(), dt_min, dt_max, worst_q, fz_drv,
              fz_sim);
}

// A stop by SIGINT: the log is flushed whole, every cycle the driver ran is in it.
TEST_F(DriverEndToEnd, TheDriversLogIsFlushedWholeAfterSigint) {
  ASSERT_EQ(RunChain({}, {"--duration", "0", "--io-arg", kBoardTimeout,
                          "--board-timeout-cycles", kBoardCycles, "--log", Path("driver.csv")},
                     2.5),
            130)
      << ReadFile(Path("driver.out"));
  runner::Table drv;
  std::string error;
  ASSERT_TRUE(drv.Load(Path("driver.csv"), &error)) << error;
  ASSERT_FALSE(summary_.is_discarded());
  EXPECT_EQ(summary_["outcome"], "interrupted");
  EXPECT_EQ(drv.rows(), summary_["cycles"].get<size_t>());
  EXPECT_GT(drv.rows(), 500u);
  const std::string text = ReadFile(Path("driver.csv"));
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');  // no half-written row
  std::printf("[ figures  ] SIGINT: %zu rows in the log, %zu cycles run\n", drv.rows(),
              summary_["cycles"].get<size_t>());
}

}  // namespace
}  // namespace ohrp::hw::udp
