// The fixture of the hw_emulator process tests (emulator_test.cc, emulator_gap_test.cc):
// hw_emulator started on HRP-1S on a free port, driven through the udp plugin the way
// hw_driver drives it.
#pragma once

#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <thread>

#include "common/process.h"
#include "common/scratch.h"
#include "hw_udp/udp_io.h"
#include "robot_model/model.h"

namespace ohrp::hw::udp::emulator_test {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr double kMaxWall = 60.0;  // [s] no test waits longer than this for the emulator

inline double Since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// The robot as the driver would know it (names, default gains) from the model.
struct Robot {
  IoConfig config;
  std::vector<double> kp, kd;
};

inline const Robot& Hrp1s() {
  static const Robot robot = [] {
    Robot r;
    std::string e;
    auto scene = model::Scene::Load(kScene, &e);
    EXPECT_TRUE(scene) << e;
    model::RobotMap map;
    EXPECT_TRUE(model::MapRobot(scene->m(), &map, &e)) << e;
    r.config.robot_name = map.name;
    for (const auto& j : map.joints) {
      r.config.joint_names.push_back(j.name);
      r.kp.push_back(j.default_kp);
      r.kd.push_back(j.default_kd);
    }
    for (const auto& f : map.forces) r.config.force_names.push_back(f.name);
    for (const auto& i : map.imus) r.config.imu_names.push_back(i.name);
    return r;
  }();
  return robot;
}

class EmulatorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ohrp::testing::ScratchFolder(
        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    err_ = (dir_ / "stderr").string();
    port_file_ = (dir_ / "port").string();
  }
  void TearDown() override {
    ohrp::testing::Kill(&pid_);
    io_.close();
    fs::remove_all(dir_);
  }

  // starts hw_emulator with `args` (after the program and its port options)
  void Spawn(std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(OHRP_BIN_DIR) + "/hw_emulator", "--port", "0",
                                     "--port-file", port_file_};
    args.insert(args.end(), extra.begin(), extra.end());
    fs::remove(port_file_);
    pid_ = ohrp::testing::Spawn(args, {.out = "/dev/null", .err = err_});
  }

  // starts hw_emulator on HRP-1S with `extra` options, on a free port; returns the port
  int Start(std::vector<std::string> extra, const char* wait_driver = "30",
            const std::string& model = kScene) {
    std::vector<std::string> args = {"--model", model, "--wait-driver", wait_driver};
    args.insert(args.end(), extra.begin(), extra.end());
    Spawn(args);
    const auto t0 = Clock::now();
    while (Since(t0) < kMaxWall) {
      std::ifstream in(port_file_);
      int port = 0;
      if (in >> port && port > 0) return port;
      if (!Running()) {
        ADD_FAILURE() << "hw_emulator ended before binding:\n" << Stderr();
        return 0;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    ADD_FAILURE() << "hw_emulator did not bind within " << kMaxWall << " s";
    return 0;
  }

  // exit code of the emulator once it ended (-1: still running after `timeout`)
  int Wait(double timeout = kMaxWall) { return ohrp::testing::WaitExit(&pid_, timeout); }
  // one look: false once the emulator ended (reaped, its code in exit_code_)
  bool Running() {
    const int code = ohrp::testing::WaitExit(&pid_, 0);
    if (code >= 0) exit_code_ = code;
    return pid_ > 0;
  }

  std::string Stderr() const {
    std::ifstream in(err_);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  // the key=value pairs of the emulator's result line
  std::map<std::string, double> Result() const {
    std::map<std::string, double> r;
    const std::string text = Stderr();
    const size_t at = text.rfind("hw_emulator: result ");
    if (at == std::string::npos) return r;
    std::istringstream line(text.substr(at + 20, text.find('\n', at) - at - 20));
    std::string kv;
    while (line >> kv) {
      const size_t eq = kv.find('=');
      if (eq != std::string::npos) r[kv.substr(0, eq)] = std::stod(kv.substr(eq + 1));
    }
    return r;
  }

  void OpenIo(int port, std::vector<std::string> extra = {}) {
    IoConfig c = Hrp1s().config;
    c.period = 0.001;
    c.args = {"port=" + std::to_string(port), "quiet=1"};
    c.args.insert(c.args.end(), extra.begin(), extra.end());
    std::string e;
    ASSERT_TRUE(io_.open(c, &e)) << e;
  }

  // The driver's loop at 1 kHz (absolute deadlines) until the emulator ends: read, then once
  // every motor board has answered, hold the first pose read (all servos on, default gains);
  // `each` may change the commands. Returns the emulator's exit code.
  int Drive(const std::function<void(const IoState&, IoCommand*)>& each = nullptr) {
    const Robot& r = Hrp1s();
    const int n = static_cast<int>(r.kp.size());
    bool holding = false;
    auto deadline = Clock::now();
    const auto t0 = Clock::now();
    while (Running() && Since(t0) < kMaxWall) {
      io_.read(&state_);
      if (!holding) {
        holding = true;
        for (int b = 0; b < io_.layout().sensor_board(); ++b)
          holding = holding && io_.stats().board[b].received > 0;
        if (holding) {
          for (int j = 0; j < n; ++j) {
            cmd_.servo_on[j] = true;
            cmd_.joint[j].mode = shm::JointMode::kPosition;
            cmd_.joint[j].q_ref = state_.q[j];
            cmd_.joint[j].kp = r.kp[j];
            cmd_.joint[j].kd = r.kd[j];
          }
        }
      }
      if (holding) {
        if (each) each(state_, &cmd_);
        io_.write(cmd_);
      }
      deadline += std::chrono::microseconds(1000);
      if (Clock::now() > deadline + std::chrono::milliseconds(100)) deadline = Clock::now();
      std::this_thread::sleep_until(deadline);
    }
    const int code = Running() ? -1 : exit_code_;
    return code;
  }

  fs::path dir_;
  std::string err_, port_file_;
  pid_t pid_ = -1;
  int exit_code_ = -1;
  UdpIo io_;
  IoState state_;
  IoCommand cmd_;
};

}  // namespace ohrp::hw::udp::emulator_test
