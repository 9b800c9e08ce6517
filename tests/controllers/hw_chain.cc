#include "hw_chain.h"

#include <signal.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/scratch.h"
#include "fake_robot.h"
#include "shm_bridge/bridge.h"

namespace ohrp::controllers::testing {

namespace fs = std::filesystem;

namespace {
const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
constexpr double kWall = 120.0;  // [s] no wait is longer

// the emulator's CSV log (a header line, then time,base_z,tilt_deg,servos_on,silent,stuck,
// saturated,estop,base_x,base_y,yaw_deg)
std::vector<EmulatorRow> ReadEmulatorLog(const std::string& path) {
  std::vector<EmulatorRow> rows;
  std::ifstream log(path);
  std::string line;
  std::getline(log, line);
  while (std::getline(log, line)) {
    EmulatorRow r;
    unsigned silent = 0, stuck = 0, saturated = 0;
    int estop = 0;
    if (std::sscanf(line.c_str(), "%lf,%lf,%lf,%d,%u,%u,%u,%d,%lf,%lf,%lf", &r.t, &r.z, &r.tilt,
                    &r.on, &silent, &stuck, &saturated, &estop, &r.x, &r.y, &r.yaw) == 11)
      rows.push_back(r);
  }
  return rows;
}
}  // namespace

std::string ChainScene() { return kScene; }

Chain RunChain(const std::string& tag, const std::vector<std::string>& controller,
               const std::vector<std::string>& emulator_args, double duration,
               Tolerance tolerance) {
  return RunChainOn({kScene, "halfsit"}, tag, controller, emulator_args, duration, tolerance);
}

Chain RunChainOn(const ChainRobot& robot, const std::string& tag,
                 const std::vector<std::string>& controller,
                 const std::vector<std::string>& emulator_args, double duration,
                 Tolerance tolerance) {
  Chain c;
  const fs::path dir = ohrp::testing::ScratchFolder(tag);
  auto path = [&](const char* f) { return (dir / f).string(); };
  // the emulator first: it writes its port once it listens
  std::vector<std::string> e = {Program("hw_emulator"), "--model", robot.model, "--keyframe",
                                robot.keyframe, "--port", "0", "--port-file", path("port"),
                                "--wait-driver", "60", "--log", path("emu.csv"), "--log-every",
                                "10"};
  e.insert(e.end(), emulator_args.begin(), emulator_args.end());
  const pid_t emulator = Spawn(e, path("emu.out"));
  int port = 0;
  for (double t = 0; port == 0 && t < kWall && ohrp::testing::Running(emulator); t += 0.01) {
    std::ifstream in(path("port"));
    if (!(in >> port)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_NE(port, 0) << ReadFile(path("emu.out"));
  // the driver, then the controller once the segment exists
  const std::string segment = UniqueSegment(tag);
  std::vector<std::string> d = {Program("hw_driver"), "--model", robot.model, "--io", Program("../lib/libohrp_io_udp.so"),
       "--io-arg", "port=" + std::to_string(port), "--io-arg",
       "timeout_ms=" + std::to_string(tolerance.board_ms), "--segment", segment, "--period",
       std::to_string(robot.period), "--watchdog-cycles", std::to_string(tolerance.cycles), "--board-timeout-cycles",
       std::to_string(tolerance.cycles), "--rt-priority", "0", "--no-mlock", "--duration",
       std::to_string(duration), "--summary", path("driver.json")};
  d.insert(d.end(), robot.driver_args.begin(), robot.driver_args.end());
  const pid_t driver = Spawn(d, path("driver.out"));
  const std::string shm_path = "/dev/shm/" + shm::SegmentObjectName(segment);
  for (double t = 0; !fs::exists(shm_path) && t < kWall && ohrp::testing::Running(driver); t += 0.01)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::vector<std::string> args = controller;
  if (args[0].find('/') == std::string::npos) args[0] = Program(args[0]);  // else a path
  args.insert(args.end(), {"--segment", segment});
  const pid_t program = Spawn(args, path("controller.out"));
  // the driver's end ends the controller; the emulator runs until told
  c.driver = WaitExit(driver, duration + kWall);
  c.controller = WaitExit(program, kWall);
  kill(emulator, SIGINT);
  c.emulator = WaitExit(emulator, kWall);
  c.controller_out = ReadFile(path("controller.out"));
  c.driver_out = ReadFile(path("driver.out"));
  c.emulator_out = ReadFile(path("emu.out"));
  c.rows = ReadEmulatorLog(path("emu.csv"));
  c.summary = nlohmann::json::parse(ReadFile(path("driver.json")), nullptr, false);
  fs::remove_all(dir);
  RemoveSegment(segment);
  return c;
}

std::string Diagnosis(const Chain& c) {
  return "exit codes: driver " + std::to_string(c.driver) + ", controller " +
         std::to_string(c.controller) + ", emulator " + std::to_string(c.emulator) +
         "\ndriver summary: " + c.summary.dump() + "\n--- driver\n" + c.driver_out +
         "--- controller\n" + c.controller_out + "--- emulator\n" + c.emulator_out;
}

std::array<double, 3> Span(const Chain& c, double t0, double t1) {
  std::array<double, 3> s = {1e9, -1e9, 0};
  int n = 0;
  for (const EmulatorRow& r : c.rows) {
    if (r.t < t0 || r.t > t1 || r.on != 29) continue;
    ++n;
    s[0] = std::min(s[0], r.z);
    s[1] = std::max(s[1], r.z);
    s[2] = std::max(s[2], r.tilt);
  }
  EXPECT_GT(n, 20) << "emulator log rows in [" << t0 << ", " << t1 << "] s";
  return s;
}

std::string MissingHwProgram(const std::string& controller) {
  for (const std::string& p : {std::string("hw_driver"), std::string("hw_emulator"), controller,
                               std::string("../lib/libohrp_io_udp.so")}) {
    const std::string path = p.find('/') == std::string::npos || p[0] == '.' ? Program(p) : p;
    if (!fs::exists(path)) return path;
  }
  return "";
}

}  // namespace ohrp::controllers::testing
