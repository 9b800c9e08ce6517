// issue 28 items 1 and 5 on the runner's side: a scenario fails on a fall with the fall's time and
// cause unless it declares `expect_fall: true` (then it fails without one); names of a scenario
// are checked against its scene before anything runs, and a shell command in a joint name is
// refused and never executed; the runner's child processes get argument vectors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "common/scratch.h"
#include "controllers/runner.h"
#include "runner/commands.h"
#include "runner/runner.h"
#include "runner/scenario.h"
#include "tool_process/run_command.h"

namespace ohrp::runner {
namespace {

namespace fs = std::filesystem;

// A rigid one-legged robot (a torso box on a leg with the sole F_SOLE, a motorised arm) started
// 11.5 deg from upright on its sole's edge: sim_host's servo holds it and it tips onto its torso
// within a second (the same robot as tests/sim_host/fall_test.cc).
constexpr const char* kTipper = R"(
<mujoco model="tipper">
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="torso" pos="0.109269 0 0.559770" quat="0.995004165 0 0.099833417 0">
      <freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/>
      <geom type="capsule" fromto="0 0 0 0.6 0 0" size="0.02"/>
      <body name="leg">
        <geom type="capsule" fromto="0 0 -0.1 0 0 -0.5" size="0.03" contype="0" conaffinity="0"/>
        <body name="foot" pos="0 0 -0.55"><geom name="F_SOLE" type="box" size="0.05 0.05 0.01"/></body>
      </body>
      <body name="arm" pos="0 0.15 0">
        <joint name="shoulder" type="hinge" axis="0 1 0" armature="0.1"/>
        <geom type="sphere" size="0.02" mass="0.1"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor name="shoulder" joint="shoulder"/></actuator>
</mujoco>
)";

// the tipper's scenario with `extra` lines; no controller (the servo holds the start pose)
std::string TipperScenario(const std::string& scene, const std::string& extra) {
  return "name: tipper\nscene: " + scene + "\nduration: 3\ncontact: native\ncontrollers: []\n" +
         "checks:\n  - {type: max_rejected, max: 0}\n" + extra;
}

RunOptions Options(const std::string& out) {
  RunOptions o;
  o.out_dir = out;
  o.source_dir = OHRP_SOURCE_DIR;
  o.bin_dir = OHRP_BIN_DIR;
  o.plot = false;
  o.echo = false;
  o.report = false;
  return o;
}

// runs scenario `text` into a fresh folder; its summary.json's check `name`
int RunText(const std::string& text, nlohmann::json* check, const std::string& name = "sim_host_completed") {
  const std::string file = ohrp::testing::ScratchFile("scenario", text, ".yaml");
  Scenario s;
  std::string error;
  EXPECT_TRUE(LoadScenario(file, &s, &error)) << error;
  const std::string out = ohrp::testing::ScratchPath("run");
  const int rc = RunScenario(s, Options(out));
  nlohmann::json j;
  std::ifstream(out + "/summary.json") >> j;
  for (const auto& c : j["checks"])
    if (c["name"] == name) *check = c;
  return rc;
}

TEST(Falls, AScenarioWhoseRobotFallsFailsWithTheFallsTimeAndCause) {
  const std::string scene = ohrp::testing::ScratchFile("tipper", kTipper, ".xml");
  nlohmann::json c;
  EXPECT_EQ(RunText(TipperScenario(scene, ""), &c), kRunFailed);
  ASSERT_TRUE(c.is_object());
  EXPECT_FALSE(c["passed"].get<bool>());
  EXPECT_EQ(c["value"], 6);
  const std::string detail = c["detail"];
  EXPECT_EQ(detail.rfind("fell at t=", 0), 0u) << detail;
  EXPECT_NE(detail.find("touched floor"), std::string::npos) << detail;
}

TEST(Falls, ExpectFallPassesOnAFallAndFailsWithoutOne) {
  const std::string scene = ohrp::testing::ScratchFile("tipper", kTipper, ".xml");
  nlohmann::json c;
  EXPECT_EQ(RunText(TipperScenario(scene, "expect_fall: true\n"), &c), kRunPassed) << c.dump();
  EXPECT_TRUE(c["passed"].get<bool>());
  EXPECT_NE(c["detail"].get<std::string>().find("as expected: fell at t="), std::string::npos) << c.dump();
  // the same robot hung by a weld cannot fall: a run that expects a fall fails
  std::string hung = kTipper;
  hung.replace(hung.find("  <actuator>"), 0, "  <equality><weld body1=\"torso\"/></equality>\n");
  const std::string hung_scene = ohrp::testing::ScratchFile("hung", hung, ".xml");
  EXPECT_EQ(RunText(TipperScenario(hung_scene, "expect_fall: true\n"), &c), kRunFailed);
  EXPECT_FALSE(c["passed"].get<bool>());
  EXPECT_NE(c["detail"].get<std::string>().find("expected a fall and the robot did not fall"),
            std::string::npos) << c.dump();
}

TEST(Falls, TheImplicitCheckReadsSimHostsFall) {
  Scenario s;
  const nlohmann::json fell = {{"outcome", "fell"},
                               {"fall", {{"time", 1.2345}, {"cycle", 246}, {"cause", "body X touched floor"}}}};
  CheckResult r = SimHostCompleted(s, 6, fell, "");
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.detail, "fell at t=1.234 s (cycle 246): body X touched floor");
  s.expect_fall = true;
  EXPECT_TRUE(SimHostCompleted(s, 6, fell, "").passed);
  EXPECT_FALSE(SimHostCompleted(s, 0, {{"outcome", "completed"}}, "").passed);
  EXPECT_FALSE(SimHostCompleted(s, 4, {{"outcome", "diverged"}}, "").passed);
  EXPECT_FALSE(SimHostCompleted(s, 6, fell, "wall-time limit").passed);  // stopped: not a result
  s.expect_fall = false;
  EXPECT_TRUE(SimHostCompleted(s, 0, {{"outcome", "completed"}, {"fall", nullptr}}, "").passed);
}

// A controller that saw the fall first (exit 8) and left: sim_host then lost its controller
// (exit 5, no fall of its own yet); the run is a fall in the controller's own words
TEST(Falls, AControllersOwnFallReportIsAFall) {
  static_assert(ohrp::runner::kControllerExitFell == ohrp::controllers::kExitFell);
  const std::string out = ohrp::testing::ScratchFile(
      "posture.stderr",
      "posture: attached\nposture: the robot fell at t = 4.515 s (cycle 903): its base tilted "
      "19.0 deg\n", ".txt");
  EXPECT_EQ(ControllerFall("posture", 0, out), "");
  EXPECT_EQ(ControllerFall("posture", 5, out), "");
  const std::string said = ControllerFall("posture", 8, out);
  EXPECT_EQ(said, "controller 'posture' saw the robot fall: posture: the robot fell at t = 4.515 s "
                  "(cycle 903): its base tilted 19.0 deg");
  Scenario s;
  const nlohmann::json lost = {{"outcome", "controller_lost"}, {"detail", "controller detached"}};
  CheckResult r = SimHostCompleted(s, 5, lost, "", said);
  EXPECT_FALSE(r.passed);
  EXPECT_EQ(r.detail, said + " (sim_host: controller_lost: controller detached)");
  // even when sim_host itself completed, a controller's fall fails the run
  EXPECT_FALSE(SimHostCompleted(s, 0, {{"outcome", "completed"}}, "", said).passed);
  s.expect_fall = true;
  r = SimHostCompleted(s, 5, lost, "", said);
  EXPECT_TRUE(r.passed);
  EXPECT_EQ(r.detail.rfind("as expected: controller 'posture' saw the robot fall", 0), 0u) << r.detail;
  EXPECT_FALSE(SimHostCompleted(s, 5, lost, "", "").passed);  // lost without a fall: no
}

TEST(Falls, TheFallKeysReachSimHost) {
  Scenario s;
  std::string error;
  ASSERT_TRUE(ParseScenario(TipperScenario("x.xml", "on_fall: continue\nfall_allow_contact: [arm, leg]\nexpect_fall: true\n"),
                            "t.yaml", &s, &error)) << error;
  EXPECT_TRUE(s.expect_fall);
  const auto argv = SimHostCommand(s, "sim_host", "x.xml", "seg", "/out");
  const std::string line = [&] {
    std::string l;
    for (const auto& a : argv) l += a + " ";
    return l;
  }();
  EXPECT_NE(line.find("--on-fall continue "), std::string::npos) << line;
  EXPECT_NE(line.find("--fall-allow-contact arm,leg "), std::string::npos) << line;
}

// issue 28 item 5: the joint name of the issue is refused before anything runs, and its command
// never runs (no file 'pwned' anywhere the runner could run it)
TEST(Names, AShellCommandInAJointNameIsRefusedAndNeverRuns) {
  const std::string cwd = fs::current_path().string();
  const std::string out = ohrp::testing::ScratchPath("injected");
  const std::string file = ohrp::testing::ScratchFile(
      "injection",
      "scene: mjcf/hrp1s/scene_flat.xml\nduration: 0.5\ncontrollers: []\nchecks:\n"
      "  - {type: max_rejected}\nplot_joints: [\"RLEG_KNEE;touch${IFS}pwned;echo\"]\n",
      ".yaml");
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(file, &s, &error)) << error;
  ::testing::internal::CaptureStderr();
  EXPECT_EQ(RunScenario(s, Options(out)), kRunUsage);
  const std::string said = ::testing::internal::GetCapturedStderr();
  EXPECT_NE(said.find("line 6: plot_joints[0]: 'RLEG_KNEE;touch${IFS}pwned;echo' is not a joint of the robot"),
            std::string::npos) << said;
  EXPECT_FALSE(fs::exists(out));  // nothing started
  EXPECT_FALSE(fs::exists(cwd + "/pwned"));
  EXPECT_FALSE(fs::exists(std::string(OHRP_SOURCE_DIR) + "/pwned"));
}

TEST(Names, UnknownSensorsBodiesAndTorquesAreRefusedWithTheirKeys) {
  auto refused = [](const std::string& extra, const std::string& message) {
    Scenario s;
    std::string error;
    ASSERT_TRUE(ParseScenario("scene: mjcf/hrp1s/scene_flat.xml\nduration: 1\ncontrollers: []\nchecks:\n" + extra,
                              "n.yaml", &s, &error)) << error;
    EXPECT_FALSE(CheckScenarioNames(s, std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &error));
    EXPECT_NE(error.find(message), std::string::npos) << error;
  };
  refused("  - {type: feet_carry_weight, sensors: [rfsensor, lfsesnor]}\n",
          "scenario 'n.yaml': line 5: checks[0] (feet_carry_weight): sensors[1]: 'lfsesnor' is not a force sensor");
  refused("  - {type: max_rejected}\nplot_torques: [RLEG_KNEE, KNEE]\n", "line 6: plot_torques[1]: 'KNEE' is not a joint");
  refused("  - {type: max_rejected}\nfall_allow_contact: [HAND]\n", "line 6: fall_allow_contact[0]: 'HAND' is not a body");
  // the shipped stand scenario names only what its scene has
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(std::string(OHRP_SOURCE_DIR) + "/scenarios/stand.yaml", &s, &error)) << error;
  EXPECT_TRUE(CheckScenarioNames(s, std::string(OHRP_SOURCE_DIR) + "/" + s.scene, &error)) << error;
}

// every shipped scenario names only what its scene has (scenes of ../shared/external that are
// not there are skipped)
TEST(Names, EveryShippedScenarioNamesWhatItsSceneHas) {
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(std::string(OHRP_SOURCE_DIR) + "/scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    Scenario s;
    std::string error;
    ASSERT_TRUE(LoadScenario(entry.path().string(), &s, &error)) << error;
    const std::string scene = s.scene[0] == '/' ? s.scene : std::string(OHRP_SOURCE_DIR) + "/" + s.scene;
    if (!fs::exists(scene)) continue;
    EXPECT_TRUE(CheckScenarioNames(s, scene, &error)) << error;
    ++checked;
  }
  EXPECT_GE(checked, 30);
}

// the runner's helper runs programs from argument vectors: a shell's metacharacters are text
TEST(Names, ArgumentsNeverReachAShell) {
  const std::string dir = ohrp::testing::ScratchFolder("argv");
  const std::string out = dir + "/out.txt";
  std::string error;
  const std::string evil = "x;touch " + dir + "/pwned;echo $(touch " + dir + "/pwned2)";
  EXPECT_EQ(tool::RunCommand({"echo", evil}, out, &error), 0) << error;
  EXPECT_EQ(ohrp::testing::ReadFile(out), evil + "\n");
  EXPECT_FALSE(fs::exists(dir + "/pwned"));
  EXPECT_FALSE(fs::exists(dir + "/pwned2"));
  EXPECT_EQ(tool::RunCommand({"sh", "-c", "exit 3"}, "", &error), 3);
  EXPECT_EQ(tool::RunCommand({"/no/such/program"}, "", &error), -1);
  EXPECT_NE(error.find("cannot run '/no/such/program'"), std::string::npos) << error;
  // a pipe into a program's standard input
  auto pipe = tool::PipeTo::Start({"cat"}, dir + "/piped.txt", &error);
  ASSERT_TRUE(pipe) << error;
  std::fputs("frames", pipe->file());
  EXPECT_EQ(pipe->Close(), 0);
  EXPECT_EQ(ohrp::testing::ReadFile(dir + "/piped.txt"), "frames");
}

}  // namespace
}  // namespace ohrp::runner
