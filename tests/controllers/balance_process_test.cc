// Cross-process tests of the built `balance` program: standing against sim_host (lock-step),
// refusing a --model that is not the producer's robot or lacks the sensors balance needs,
// refusing bad options, and holding its last posture when the sensors go NaN mid-run (a
// producer in this test that publishes a simulated robot's sensors and corrupts one of them).
#include <signal.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "fake_robot.h"
#include "shm_bridge/bridge.h"

namespace ohrp::controllers::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
const std::string kRobotFile = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml";
constexpr double kWall = 120.0;  // [s] no wait is longer (the machine may be loaded)

// waits until the producer's segment exists (true) or `timeout` [s] passed
bool WaitSegment(const std::string& segment, double timeout) {
  const std::string path = "/dev/shm/" + shm::SegmentObjectName(segment);
  for (double t = 0; t < timeout; t += 0.01) {
    if (fs::exists(path)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

// one column of a CSV log by its header name, with the time column
std::vector<std::pair<double, double>> Column(const std::string& path, const std::string& name) {
  std::ifstream in(path);
  std::string line, cell;
  std::getline(in, line);
  std::stringstream header(line);
  int col = -1;
  for (int i = 0; std::getline(header, cell, ','); ++i)
    if (cell == name) col = i;
  std::vector<std::pair<double, double>> out;
  if (col < 0) return out;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    double t = 0, v = 0;
    for (int i = 0; std::getline(row, cell, ','); ++i) {
      if (i == 0) t = std::stod(cell);
      if (i == col) v = std::stod(cell);
    }
    out.emplace_back(t, v);
  }
  return out;
}

// a copy of the robot file with `edit` applied, in a fresh directory next to an unchanged copy
// of the flat scene (which includes "hrp1s.xml"); returns the robot file's path
std::string EditedRobot(const std::string& tag, const std::function<void(std::string*)>& edit) {
  const std::string base = TempPath(tag);
  const fs::path dir = base + "_dir";
  fs::remove(base);
  fs::create_directories(dir);
  std::string text = ReadFile(kRobotFile);
  edit(&text);
  WriteText((dir / "hrp1s.xml").string(), text);
  fs::copy_file(kScene, dir / "scene_flat.xml", fs::copy_options::overwrite_existing);
  return (dir / "hrp1s.xml").string();
}

// removes every line of `*text` containing `needle`; the number removed
int RemoveLines(std::string* text, const std::string& needle) {
  std::stringstream in(*text);
  std::string line, out;
  int removed = 0;
  while (std::getline(in, line)) {
    if (line.find(needle) != std::string::npos) {
      ++removed;
      continue;
    }
    out += line + "\n";
  }
  *text = out;
  return removed;
}

// runs balance with `args` without a producer (a segment nobody created); exit code, output
int RunAlone(std::vector<std::string> args, std::string* output) {
  const std::string log = TempPath("balance_alone");
  std::vector<std::string> a = {Program("balance"), "--segment", UniqueSegment("nobody")};
  a.insert(a.end(), args.begin(), args.end());
  const int code = WaitExit(Spawn(a, log), kWall);
  *output = ReadFile(log);
  fs::remove(log);
  return code;
}

// 1. the program stands the robot on sim_host: base height steady once standing
TEST(BalanceProcess, StandsOnSimHost) {
  const std::string segment = UniqueSegment("bal_sim");
  const std::string csv = TempPath("bal_sim_csv"), sim_out = TempPath("bal_sim_out"),
                    bal_out = TempPath("bal_sim_bal"), summary = TempPath("bal_sim_json");
  const pid_t sim = Spawn({Program("sim_host"), "--scene", kScene, "--keyframe", "halfsit",
                           "--segment", segment, "--duration", "5", "--log", csv, "--summary",
                           summary, "--progress", "0"},
                          sim_out);
  ASSERT_TRUE(WaitSegment(segment, kWall)) << ReadFile(sim_out);
  const pid_t bal = Spawn({Program("balance"), "--segment", segment}, bal_out);
  ASSERT_EQ(WaitExit(sim, kWall), 0) << ReadFile(sim_out);
  ASSERT_EQ(WaitExit(bal, kWall), 0) << ReadFile(bal_out);
  const std::string report = ReadFile(bal_out);
  EXPECT_NE(report.find("balance: stood"), std::string::npos) << report;
  EXPECT_EQ(report.find("HELD"), std::string::npos) << report;
  const auto j = nlohmann::json::parse(ReadFile(summary), nullptr, false);
  ASSERT_FALSE(j.is_discarded());
  EXPECT_EQ(j["rejected_commands"], 0);

  // ramp 2 s + settle 0.5 s + CoM centring 1 s: standing from 3.5 s; the base height then
  // stays within 3 mm of its value at 3.5 s, and within 2 cm of the keyframe's 0.6839 m
  const auto z = Column(csv, "base_z");
  ASSERT_GT(z.size(), 900u);
  double z_stance = NAN, lo = 1e9, hi = -1e9;
  for (const auto& [t, v] : z) {
    if (t < 3.5) continue;
    if (std::isnan(z_stance)) z_stance = v;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_NEAR(z_stance, 0.6839, 0.02);
  EXPECT_LT(hi - z_stance, 0.003);
  EXPECT_LT(z_stance - lo, 0.003);
  // upright: the base's tilt (the angle of its z axis from the vertical) below 3 degrees
  const auto qw = Column(csv, "base_qw"), qz = Column(csv, "base_qz");
  ASSERT_EQ(qw.size(), qz.size());
  double tilt_max = 0;
  for (std::size_t i = 0; i < qw.size(); ++i) {
    const double c = std::sqrt(qw[i].second * qw[i].second + qz[i].second * qz[i].second);
    tilt_max = std::max(tilt_max, 2 * std::acos(std::min(1.0, c)) * 180 / M_PI);
  }
  EXPECT_LT(tilt_max, 3.0);
  std::printf("[ figures  ] balance on sim_host: base z at 3.5 s %.4f m, %.4f..%.4f m to 5 s; "
              "tilt max %.2f deg\n%s",
              z_stance, lo, hi, tilt_max, report.c_str());
  for (const auto& f : {csv, sim_out, bal_out, summary}) fs::remove(f);
}

// 3. a --model whose CHEST weighs 1 kg more is refused at configure, naming the difference
TEST(BalanceProcess, RefusesAProducerWhoseRobotDiffers) {
  const std::string copy = EditedRobot("bal_heavy", [](std::string* text) {
    const std::size_t chest = text->find("<body name=\"CHEST\"");
    const std::size_t at = text->find("mass=\"", chest) + 6;
    const std::size_t end = text->find('"', at);
    const double mass = std::stod(text->substr(at, end - at));
    text->replace(at, end - at, std::to_string(mass + 1.0));
  });
  const std::string segment = UniqueSegment("bal_mismatch");
  const std::string sim_out = TempPath("bal_mm_sim"), bal_out = TempPath("bal_mm_bal"),
                    summary = TempPath("bal_mm_json");
  const pid_t sim = Spawn({Program("sim_host"), "--scene", kScene, "--keyframe", "halfsit",
                           "--segment", segment, "--duration", "60", "--realtime",
                           "--wait-controller", "0", "--summary", summary, "--progress", "0"},
                          sim_out);
  ASSERT_TRUE(WaitSegment(segment, kWall)) << ReadFile(sim_out);
  const int code = WaitExit(Spawn({Program("balance"), "--segment", segment, "--model", copy},
                                  bal_out),
                            kWall);
  const std::string err = ReadFile(bal_out);
  EXPECT_EQ(code, 3) << err;
  EXPECT_NE(err.find("--model " + copy + ": the producer's robot is not this model's robot"),
            std::string::npos) << err;
  EXPECT_NE(err.find("'CHEST' moves a body of 13 kg in the segment, 14 kg here"),
            std::string::npos) << err;
  EXPECT_NE(err.find("hash"), std::string::npos) << err;
  // the producer ran in real time without a controller all along; stopped now
  kill(sim, SIGINT);
  const int sim_code = WaitExit(sim, kWall);
  const auto j = nlohmann::json::parse(ReadFile(summary), nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << ReadFile(sim_out);
  EXPECT_EQ(j["commands"], 0) << "the producer received commands from a refused controller";
  // (balance claims the controller slot to read the header, then releases it: the producer
  // may count it as seen, but it never answered a cycle)
  std::printf("[ figures  ] sim_host exit %d, commands %s, controllers seen %s; balance said: %s",
              sim_code, j["commands"].dump().c_str(), j["controllers_seen"].dump().c_str(),
              err.c_str());
  for (const auto& f : {sim_out, bal_out, summary}) fs::remove(f);
  fs::remove_all(fs::path(copy).parent_path());
}

// 4. a robot without the left ankle's F/T sensor, or without the IMU: refused before attaching
// (exit 3, not 4: the segment does not exist), saying what balance needs
TEST(BalanceProcess, RefusesARobotWithoutAnkleSensorsOrImu) {
  const std::string no_ft = EditedRobot("bal_noft", [](std::string* text) {
    ASSERT_EQ(RemoveLines(text, "site=\"lfsensor\"/>"), 2);
  });
  std::string out;
  EXPECT_EQ(RunAlone({"--model", no_ft}, &out), 3) << out;
  EXPECT_NE(out.find("1 requirement missing (all listed):\n  - a force/torque sensor above sole LLEG_SOLE"),
            std::string::npos) << out;
  std::printf("[ figures  ] no left ankle F/T: %s", out.c_str());

  const std::string no_imu = EditedRobot("bal_noimu", [](std::string* text) {
    ASSERT_EQ(RemoveLines(text, "site=\"imu\"/>"), 2);
  });
  EXPECT_EQ(RunAlone({"--model", no_imu}, &out), 3) << out;
  EXPECT_NE(out.find("1 requirement missing (all listed):\n  - an IMU"), std::string::npos) << out;
  std::printf("[ figures  ] no IMU: %s", out.c_str());
  for (const auto& f : {no_ft, no_imu}) fs::remove_all(fs::path(f).parent_path());
}

// 4b. a robot lacking several things (issue 31: no *_SOLE boxes, no IMU, a pose of another
// robot): every requirement in one refusal, each with what would satisfy it, the F/T sensors
// included although there are no soles to put them above
TEST(BalanceProcess, ListsEveryMissingRequirementAtOnce) {
  const std::string bare = EditedRobot("bal_bare", [](std::string* text) {
    ASSERT_EQ(RemoveLines(text, "site=\"imu\"/>"), 2);
    for (const char* sole : {"LLEG_SOLE", "RLEG_SOLE"}) {
      const std::size_t at = text->find(sole);
      ASSERT_NE(at, std::string::npos);
      text->replace(at, std::strlen(sole), std::string(sole, 4) + "_FOOT");
    }
  });
  const std::string pose = fs::path(bare).parent_path().string() + "/other_robot.yaml";
  WriteText(pose, "joints:\n  left_knee_joint: 0.3\n");
  std::string out;
  EXPECT_EQ(RunAlone({"--model", bare, "--pose", pose}, &out), 3) << out;
  for (const char* item : {"4 requirements missing (all listed):", "\n  - two soles: a box geom whose name ends in _SOLE",
                           "\n  - a force/torque sensor in each foot: a <force> and a <torque>",
                           "\n  - an IMU: a <gyro> and an <accelerometer>",
                           "\n  - a stance pose for this robot's joints (--keyframe NAME of the model, or --pose FILE", "no joint left_knee_joint"})
    EXPECT_NE(out.find(item), std::string::npos) << item << " not in:\n" << out;
  std::printf("[ figures  ] bare robot: %s", out.c_str());
  fs::remove_all(fs::path(bare).parent_path());
}

// 6. bad options: exit 2 naming the option; a missing --model file too, naming it
TEST(BalanceProcess, RefusesBadOptions) {
  std::string out;
  EXPECT_EQ(RunAlone({"--k-dcm", "-1"}, &out), 2) << out;
  EXPECT_NE(out.find("--k-dcm"), std::string::npos) << out;
  EXPECT_EQ(RunAlone({"--ramp", "nan"}, &out), 2) << out;
  EXPECT_NE(out.find("--ramp"), std::string::npos) << out;
  EXPECT_EQ(RunAlone({"--ankle-damping", "0"}, &out), 2) << out;
  EXPECT_NE(out.find("--ankle-damping"), std::string::npos) << out;
  EXPECT_EQ(RunAlone({"--model", "/nonexistent/robot.xml"}, &out), 2) << out;
  EXPECT_NE(out.find("--model"), std::string::npos) << out;
  EXPECT_NE(out.find("/nonexistent/robot.xml"), std::string::npos) << out;
  std::printf("[ figures  ] missing model: %s", out.c_str());
}

}  // namespace
}  // namespace ohrp::controllers::testing
