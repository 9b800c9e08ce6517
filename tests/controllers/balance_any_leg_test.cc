// issue 31 item 2: balance on a robot that is not HRP-1S. Unitree H1 (menagerie, 5-joint legs:
// no ankle roll) standing free on the soft soles, with what balance needs added in a scratch
// copy the way a robot profile would (sole boxes LLEG_SOLE/RLEG_SOLE under the foot capsules,
// a force/torque site on each ankle link, an IMU on the pelvis) and its stance from the
// scene's "stand" keyframe (--keyframe). Today's code has neither --keyframe nor --servo-hz,
// and its leg IK, asked for 6-D sole poses that a 5-joint leg cannot reach, failed in most
// cycles (the issue: 2835 failures, a fall at 1.26 s).
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <vector>

#include "common/scratch.h"
#include "controllers/runner.h"
#include "fake_robot.h"
#include "in_process_run.h"

namespace ohrp::controllers::testing {
namespace {

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void Replace(std::string* text, const std::string& from, const std::string& to) {
  const size_t at = text->find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text->replace(at, from.size(), to);
}

// H1 with soles, ankle F/T and a pelvis IMU, and the free-standing scene with its "stand" key
// (scenarios/scenes/h1_free.xml), in a scratch folder; "" when ../shared/external is absent
std::string AugmentedH1() {
  const std::string external = ExternalDir();
  if (external.empty()) return "";
  const std::string h1 = external + "/menagerie/unitree_h1";
  std::string robot = Read(h1 + "/h1.xml");
  for (const std::string side : {"left", "right"}) {
    const std::string sole = side == "left" ? "LLEG_SOLE" : "RLEG_SOLE";
    // the capsules span x -0.049 .. 0.154, y +-0.044, their bottom at z -0.07
    Replace(&robot, "<geom class=\"visual\" mesh=\"" + side + "_ankle_link\"/>",
            "<geom class=\"visual\" mesh=\"" + side + "_ankle_link\"/><geom name=\"" + sole +
                "\" type=\"box\" size=\"0.1 0.04 0.005\" pos=\"0.0525 0 -0.065\" contype=\"0\" "
                "conaffinity=\"0\" group=\"3\"/><site name=\"" + side + "_ft\"/>");
  }
  Replace(&robot, "<geom class=\"visual\" mesh=\"pelvis\"/>",
          "<geom class=\"visual\" mesh=\"pelvis\"/><site name=\"imu_pelvis\"/>");
  Replace(&robot, "</mujoco>",
          "<sensor><gyro site=\"imu_pelvis\"/><accelerometer site=\"imu_pelvis\"/>"
          "<force site=\"left_ft\"/><torque site=\"left_ft\"/><force site=\"right_ft\"/>"
          "<torque site=\"right_ft\"/></sensor></mujoco>");
  Replace(&robot, "meshdir=\"assets\"", "meshdir=\"" + h1 + "/assets\"");
  const std::string dir = ohrp::testing::ScratchFolder("h1_any_leg");
  std::ofstream(dir + "/h1.xml") << robot;
  std::ofstream(dir + "/scene.xml")
      << "<mujoco model=\"h1 free\"><include file=\"h1.xml\"/><worldbody>"
         "<geom name=\"floor\" size=\"0 0 0.05\" type=\"plane\"/></worldbody><keyframe>"
         "<key name=\"stand\" qpos=\"0 0 0.978 1 0 0 0  0 0 -0.31 0.8 -0.49  0 0 -0.31 0.8 "
         "-0.49  0  0 0 0 0  0 0 0 0\"/></keyframe></mujoco>";
  return dir + "/scene.xml";
}

// an in-process run of balance on the augmented H1 from its "stand" key, 4 ms control;
// `extra` are balance's options after --model
InProcessRun H1Run(const std::string& scene, const std::vector<std::string>& extra, double t_end) {
  InProcessRun run;
  run.io.scene = scene;
  run.io.keyframe = "stand";
  run.io.control_period = 0.004;
  run.args = {Program("balance"), "--model", scene};
  run.args.insert(run.args.end(), extra.begin(), extra.end());
  run.t_end = t_end;
  return run;
}

// Issue 31 item 2: balance stands H1 on one contact (the soft soles alone; sim_host switches the
// foot's own geoms off) at --servo-hz 10. H1's actuators are <motor>s: the suggested 6 Hz on
// each joint's own inertia lets it sink; at 9 Hz it still falls (6.5 s), from 9.5 to 11 Hz it
// stands 20 s (tilt under 2.5 deg), at 12 Hz the servo chatters at the control rate (the pelvis'
// accelerometer reads a steady 4 m/s^2 sideways while it stands still) and balance's estimator
// reports a fall that is not. The servo's frequency is not yet derived from the robot.
TEST(BalanceAnyLeg, H1WithFiveJointLegsStandsFreeFromItsKeyframe) {
  const std::string scene = AugmentedH1();
  if (scene.empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
  const InProcessResult r = RunInProcess(
      "h1_any_leg", H1Run(scene, {"--keyframe", "stand", "--ramp", "1.0", "--servo-hz", "10", "--no-self-collision"}, 8.0));
  EXPECT_EQ(r.exit_code, kExitOk) << r.output;
  EXPECT_FALSE(r.left_early) << r.output;
  EXPECT_NE(r.output.find("balance: stood"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("; 0 leg IK results not converged"), std::string::npos) << r.output;
  EXPECT_GT(r.base_z, 0.9) << r.output;  // the stand key's pelvis at 0.978 m
  const size_t at = r.output.find("balance: stood");
  if (at != std::string::npos) std::printf("[ figures  ] %s", r.output.substr(at).c_str());
}

TEST(BalanceAnyLeg, AKeyframeTheModelLacksIsRefusedNamingIt) {
  const std::string scene = AugmentedH1();
  if (scene.empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
  const InProcessResult r =
      RunInProcess("h1_no_key", H1Run(scene, {"--keyframe", "crouch", "--no-self-collision"}, 2.0));
  EXPECT_EQ(r.exit_code, kExitUsage) << r.output;
  EXPECT_NE(r.output.find("--keyframe crouch: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("crouch"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace ohrp::controllers::testing
