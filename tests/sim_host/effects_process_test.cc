// Tests `sim_host --explain` and a run's effects lines as a process, and the scenario key
// `effects` that becomes sim_host's --effects option.
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/process.h"
#include "effects_scenes.h"
#include "runner/commands.h"
#include "runner/scenario.h"

namespace ohrp::sim {
namespace {

using testing::kFlat;

//---------------- sim_host --explain, as a process ----------------

// runs sim_host with `args`; returns its exit code, stdout and stderr in *out, *err
int RunSimHost(const std::vector<std::string>& args, std::string* out, std::string* err) {
  const std::string o = testing::WriteTemp("", ".out"), e = testing::WriteTemp("", ".err");
  std::vector<std::string> argv = {std::string(OHRP_BIN_DIR) + "/sim_host"};
  argv.insert(argv.end(), args.begin(), args.end());
  const int code = ohrp::testing::WaitExit(ohrp::testing::Spawn(argv, {.out = o, .err = e}),
                                           ohrp::testing::kNoTimeout);
  std::ifstream fo(o), fe(e);
  std::stringstream so, se;
  so << fo.rdbuf();
  se << fe.rdbuf();
  *out = so.str();
  *err = se.str();
  std::filesystem::remove(o);
  std::filesystem::remove(e);
  return code;
}

TEST(EffectsProcess, ExplainPrintsTheTableAndCreatesNoSegment) {
  const std::string segment = "effects_explain_" + std::to_string(getpid());
  std::string out, err;
  ASSERT_EQ(RunSimHost({"--scene", kFlat, "--keyframe", "halfsit", "--segment", segment,
                        "--explain"}, &out, &err), 0) << err;
  EXPECT_NE(out.find("rne_post           on     needed by force_torque, accelerometer"), std::string::npos) << out;
  EXPECT_NE(out.find("soft_contact       on"), std::string::npos);
  EXPECT_NE(out.find("cameras            on     declared by the scene (LeftCamera, RightCamera): rendered only while"), std::string::npos) << out;
  EXPECT_NE(out.find("cameras: 2 (LeftCamera first), 640x480 RGB + depth, 30 frames per simulated second, rendered only while an attached program asks for them"), std::string::npos) << out;
  EXPECT_NE(out.find("world/RLEG_ANKLE_R"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists("/dev/shm/ohrp_" + segment));
  EXPECT_TRUE(err.empty()) << err;
  // bad requests: exit 2 with the reason
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--effects", "self_contact=on"}, &out, &err), 2);
  EXPECT_NE(err.find("cannot be switched on"), std::string::npos) << err;
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--camera-size", "641x480"}, &out, &err), 2);
  EXPECT_NE(err.find("--camera-size: camera size '641x480' must be WIDTHxHEIGHT within 1x1 to 640x480"), std::string::npos) << err;
  EXPECT_EQ(RunSimHost({"--scene", kFlat, "--explain", "--effects", "gravity"}, &out, &err), 2);
  EXPECT_NE(err.find("NAME=VALUE"), std::string::npos) << err;
}

TEST(EffectsProcess, ARunPrintsTheShortTableAndSummarisesIt) {
  const std::string dir = testing::WriteTemp("", ".d");
  std::filesystem::remove(dir);
  std::filesystem::create_directory(dir);
  const std::string segment = "effects_run_" + std::to_string(getpid());
  std::string out, err;
  ASSERT_EQ(RunSimHost({"--scene", kFlat, "--keyframe", "halfsit", "--segment", segment,
                        "--wait-controller", "0", "--duration", "0.05", "--progress", "0",
                        "--log", dir + "/log.csv", "--summary", dir + "/sum.json",
                        "--effects", "log_force_torque=off,noise=on"}, &out, &err), 0) << err;
  EXPECT_NE(err.find("sim_host: effects on: gravity"), std::string::npos) << err;
  EXPECT_NE(err.find("sim_host: effects off: native_contact"), std::string::npos) << err;
  std::ifstream sum(dir + "/sum.json");
  std::stringstream ss;
  ss << sum.rdbuf();
  EXPECT_NE(ss.str().find("\"effects\""), std::string::npos);
  EXPECT_NE(ss.str().find("needed by force_torque, accelerometer"), std::string::npos);
  // the log has no F/T columns, the IMU's are there
  std::ifstream log(dir + "/log.csv");
  std::string header;
  std::getline(log, header);
  EXPECT_EQ(header.find("rfsensor_fx"), std::string::npos) << header;
  EXPECT_NE(header.find("imu_gx"), std::string::npos) << header;
  std::filesystem::remove_all(dir);
}

//---------------- the scenario key ----------------

TEST(EffectsScenario, TheKeyBecomesSimHostsEffectsOption) {
  const std::string path = testing::WriteTemp(
      "scene: mjcf/hrp1s/scene_flat.xml\nduration: 1\n"
      "effects:\n  gravity: off\n  noise: on\n  noise.force: 2.5\n"
      "controllers: []\nchecks: [{type: not_fallen}]\n", ".yaml");
  runner::Scenario s;
  std::string error;
  ASSERT_TRUE(runner::LoadScenario(path, &s, &error)) << error;
  EXPECT_EQ(s.host_options.at("effects"), "gravity=off,noise=on,noise.force=2.5");
  // passed on as one --effects in the file's order (the option table, cli/host_options.h)
  const std::vector<std::string> argv = runner::SimHostCommand(s, "sim_host", s.scene, "seg", "/out");
  const auto at = std::find(argv.begin(), argv.end(), "--effects");
  ASSERT_NE(at, argv.end());
  ASSERT_NE(at + 1, argv.end());
  EXPECT_EQ(*(at + 1), "gravity=off,noise=on,noise.force=2.5");
  EXPECT_EQ(std::count(argv.begin(), argv.end(), "--effects"), 1);
  // and sim_host reads what the scenario wrote
  EffectRequests req;
  ASSERT_TRUE(ParseEffectRequests(*(at + 1), &req, &error)) << error;
  EXPECT_EQ(req.request[static_cast<int>(Effect::kGravity)], 0);
  EXPECT_EQ(req.noise.force, 2.5);
  const std::string bad = testing::WriteTemp(
      "scene: mjcf/hrp1s/scene_flat.xml\neffects: [gravity]\n", ".yaml");
  EXPECT_FALSE(runner::LoadScenario(bad, &s, &error));
  EXPECT_NE(error.find("'effects' must be a mapping"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::sim
