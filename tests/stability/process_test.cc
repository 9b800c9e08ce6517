// Tests sim_host's divergence stop end to end, with the real programs: sim_host on a scene
// that diverges once the arm moves (mjcf/stability/stiff_spring_arm.xml) and posture moving it.
// sim_host must exit 4 with the watch's diagnostic on stderr and in its summary, posture must
// exit non-zero saying that the producer diverged, and the segment must be gone. And a body
// falling beside the robot in a scene without MuJoCo's `energy` flag is no divergence.
#include <unistd.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/process.h"
#include "common/scratch.h"
#include "shm_bridge/bridge.h"

namespace {

namespace fs = std::filesystem;

// starts `args`, its stdout and stderr into the file `out_file`
pid_t Spawn(const std::vector<std::string>& args, const std::string& out_file) {
  return ohrp::testing::Spawn(args, ohrp::testing::ToFile(out_file));
}

// exit code, or -1 after `timeout` [s] (the process is then killed)
using ohrp::testing::WaitExit;

using ohrp::testing::ReadFile;

TEST(DivergenceStop, SimHostStopsWithADiagnosticAndThePostureControllerIsTold) {
  const std::string segment = "stabtest_" + std::to_string(getpid());
  const std::string object = "/dev/shm/" + ohrp::shm::SegmentObjectName(segment);
  fs::remove(object);
  const fs::path dir = ohrp::testing::ScratchFolder("divergence");
  const std::string pose = (dir / "pose.yaml").string();
  std::ofstream(pose) << "joints:\n  j1: 0.5\n  j2: 0.3\n";
  const std::string summary = (dir / "summary.json").string();

  const std::string bin = OHRP_BIN_DIR;
  const pid_t sim = Spawn({bin + "/sim_host", "--scene",
                           std::string(OHRP_SOURCE_DIR) + "/mjcf/stability/stiff_spring_arm.xml",
                           "--segment", segment, "--control-period", "0.002", "--duration", "5",
                           "--wait-controller", "20", "--progress", "0", "--summary", summary},
                          (dir / "sim_host.txt").string());
  // posture retries attaching until the segment is there
  const pid_t posture = Spawn({bin + "/posture", "--segment", segment, "--pose", pose, "--ramp",
                               "0.5", "--attach-timeout", "20"},
                              (dir / "posture.txt").string());
  const int sim_exit = WaitExit(sim, 60);
  const int posture_exit = WaitExit(posture, 20);
  const std::string sim_text = ReadFile((dir / "sim_host.txt").string());
  const std::string posture_text = ReadFile((dir / "posture.txt").string());

  // sim_host: exit 4, the diagnostic names the step, the joint and the cause
  EXPECT_EQ(sim_exit, 4) << sim_text;
  EXPECT_NE(sim_text.find("simulation diverged"), std::string::npos) << sim_text;
  EXPECT_NE(sim_text.find("joint j2"), std::string::npos) << sim_text;
  EXPECT_NE(sim_text.find("stiffness of the joint spring on joint j2"), std::string::npos) << sim_text;
  EXPECT_NE(sim_text.find("at step "), std::string::npos) << sim_text;

  // the summary carries the same diagnostic
  std::ifstream in(summary);
  ASSERT_TRUE(in) << "no summary";
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["outcome"], "diverged");
  EXPECT_EQ(j["exit_code"], 4);
  ASSERT_TRUE(j.contains("divergence")) << j.dump(2);
  const auto& x = j["divergence"];
  EXPECT_EQ(x["dofs"][0]["joint"], "j2") << x.dump(2);
  EXPECT_EQ(x["bodies"][0], "forearm") << x.dump(2);
  EXPECT_NE(x["cause"].get<std::string>().find("joint spring"), std::string::npos) << x.dump(2);
  // it grows 2.4x per step once the arm moves: within a few tenths of a second of the start
  const double t = x["time"].get<double>();
  EXPECT_GT(t, 0.0);
  EXPECT_LT(t, 0.3);
  EXPECT_LT(j["sim_time"].get<double>(), 0.3);

  // posture: non-zero, and it says the producer diverged
  EXPECT_EQ(posture_exit, 6) << posture_text;
  EXPECT_NE(posture_text.find("diverged"), std::string::npos) << posture_text;

  // the segment is gone
  EXPECT_FALSE(fs::exists(object));
  fs::remove_all(dir);
}

// a body that is not the robot falling freely in a scene without MuJoCo's `energy` flag: 3 s
// of free fall (20 kg, 8.6 kJ of kinetic energy against a margin of 200 J) is no divergence
TEST(DivergenceStop, AFallingBodyBesideTheRobotDoesNotStopTheRun) {
  const std::string segment = "stabfall_" + std::to_string(getpid());
  const fs::path dir = ohrp::testing::ScratchFolder("fall");
  const std::string scene = (dir / "arm_and_ball.xml").string();
  std::ofstream(scene) << R"(<mujoco model="arm_and_ball">
  <option timestep="0.001"/>
  <worldbody>
    <body name="link">
      <joint name="j1" type="hinge" axis="0 1 0" limited="true" range="-1 1"/>
      <geom type="capsule" fromto="0 0 0 0.3 0 0" size="0.02" mass="1"/>
    </body>
    <body name="ball" pos="1 0 1">
      <freejoint/>
      <geom type="sphere" size="0.1" mass="20" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator><motor name="m1" joint="j1" ctrllimited="true" ctrlrange="-50 50"/></actuator>
</mujoco>)";
  const std::string summary = (dir / "summary.json").string();
  const pid_t sim = Spawn({std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", scene,
                           "--segment", segment, "--duration", "3", "--wait-controller", "0",
                           "--progress", "0", "--summary", summary},
                          (dir / "sim_host.txt").string());
  const int code = WaitExit(sim, 60);
  const std::string text = ReadFile((dir / "sim_host.txt").string());
  EXPECT_EQ(code, 0) << text;
  EXPECT_EQ(text.find("diverged"), std::string::npos) << text;
  std::ifstream in(summary);
  ASSERT_TRUE(in) << "no summary: " << text;
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_NE(j["outcome"], "diverged") << j.dump(2);
  EXPECT_NEAR(j["sim_time"].get<double>(), 3.0, 0.01) << j.dump(2);
  fs::remove_all(dir);
}

}  // namespace
