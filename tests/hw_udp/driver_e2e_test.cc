// Tests the whole hardware chain end to end with the real binaries: hw_emulator (the boards, a
// MuJoCo HRP-1S behind them) <- UDP -> hw_driver with libohrp_io_udp.so <- segment -> posture.
// posture ramps the robot to half-sitting; the emulator's log says whether it stands.
// Skipped when hw_driver or posture is not built. Bounds are generous: the machine may be loaded.
// The fixture: driver_e2e.h.
#include "driver_e2e.h"

#include "runner/checks.h"  // datalog::Table: the data logs' reader

namespace ohrp::hw::udp::e2e {
namespace {

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

// hw_driver --log writes sim_host's data log format: the same column names but the simulator's
// ground truth (base_*), read by the same reader (datalog::Table), one row per servo cycle, a
// period apart; and the values are the robot's: standing half-sitting, the joints where
// sim_host's robot has them and the feet carrying the same weight.
TEST_F(DriverEndToEnd, TheDriversLogHasSimHostsColumnsAndTheSameReaderReadsIt) {
  RunSimHost(segment_ + "s", Path("sim.csv"), Path("sim"));
  datalog::Table sim, drv;
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
  auto last = [](const datalog::Table& tb, const std::string& name) {
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
  datalog::Table drv;
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
}  // namespace ohrp::hw::udp::e2e
