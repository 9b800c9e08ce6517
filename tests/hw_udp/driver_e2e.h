// The fixture of the end-to-end tests of the hardware chain (driver_e2e_test.cc,
// driver_e2e_faults_test.cc): hw_emulator (the boards, a MuJoCo HRP-1S behind them) <- UDP ->
// hw_driver with libohrp_io_udp.so <- segment -> posture. Skipped when a binary is not built.
#pragma once
#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/process.h"
#include "runner/checks.h"  // datalog::Table: the data logs' reader
#include "common/scratch.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw::udp::e2e {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline const std::string kBin = OHRP_BIN_DIR;
inline const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr double kHalfSitHeight = 0.6839;  // base height of the half-sitting keyframe [m]
constexpr double kMaxWall = 90.0;          // [s] no wait in this test is longer

inline double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// starts `args`, its stdout and stderr into the file `out`
inline pid_t Exec(const std::vector<std::string>& args, const std::string& out) {
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
  // `during`, when given, runs once posture has started, with the boards' port.
  int RunChain(std::vector<std::string> emulator_args, std::vector<std::string> driver_args,
               double sigint_after = 0, const std::function<void(int)>& during = {}) {
    std::vector<std::string> e = {kBin + "/hw_emulator", "--model", scene_, "--port", "0",
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
        kBin + "/hw_driver", "--model", scene_, "--io", kBin + "/../lib/libohrp_io_udp.so",
        "--io-arg", "port=" + std::to_string(port), "--segment", segment_, "--summary",
        Path("driver.json")};
    // loosened for a loaded machine, unless the README's defaults are what is tested
    if (!readme_defaults_) {
      d.insert(d.end(), {"--period", "0.002", "--watchdog-cycles", "500", "--rt-priority", "0",
                         "--no-mlock"});
    }
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
    posture_ = readme_defaults_
                   ? Exec({kBin + "/posture", "--segment", segment_, "--rt-priority", "70"},
                          Path("posture.out"))
                   : Exec(PostureArgs(), Path("posture.out"));
    if (during) during(port);
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
  // posture as the chain runs it (the README's way aside): a 1 s ramp, then posture_args_
  std::vector<std::string> PostureArgs() const {
    std::vector<std::string> p = {kBin + "/posture", "--segment", segment_, "--ramp", "1.0"};
    p.insert(p.end(), posture_args_.begin(), posture_args_.end());
    return p;
  }
  std::string scene_ = kScene;             // RunChain: the robot of the emulator and the driver
  std::vector<std::string> posture_args_;  // RunChain: posture's further options
  bool readme_defaults_ = false;  // RunChain: hw_driver and posture as the README runs them
  std::string segment_;
  fs::path dir_;
  pid_t emulator_ = -1, driver_ = -1, posture_ = -1;
};

}  // namespace ohrp::hw::udp::e2e
