// Issue 28, item 6 for the controllers: every numeric option of walk, balance, posture,
// playback and track_ball is checked against the plausible-range table (cli/plausible.h) and,
// where the controller knows its robot (the model), narrowed further; footstep files are checked
// against the walk's limits and the robot's physics (height change, swing apex, step time) BEFORE
// anything attaches: each refusal is exit 2 with the range (and file, line, key) named, and no
// segment is needed to get it. A speed that will be capped says so on stderr at once.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/scratch.h"
#include "controllers/runner.h"
#include "fake_robot.h"

namespace ohrp::controllers::testing {
namespace {

// runs `name` with `args` (no producer anywhere): exit code, stdout and stderr in *output
int RunProgram(const std::string& name, std::vector<std::string> args, std::string* output) {
  const std::string log = TempPath("opt_" + name);
  args.insert(args.begin(), Program(name));
  const int code = WaitExit(Spawn(args, log), 30.0);
  *output = ReadFile(log);
  return code;
}

const std::string kNoSegment = "ohrp_options_test_no_such_segment";

struct Refused {
  std::string program;
  std::vector<std::string> args;
  std::string expect;  // in the message: the range
};

TEST(ControllerOptions, AbsurdValuesAreRefusedWithThePlausibleRange) {
  const std::vector<Refused> cases = {
      {"walk", {"--max-stride", "1e308"}, "[0, 1.5] m"},
      {"walk", {"--step-time", "0.01"}, "[0.2, 5] s"},
      {"walk", {"--step-height", "0.9"}, "[0, 0.5] m"},
      {"walk", {"--k-dcm", "1e308"}, "[0, 1000] 1/s"},
      {"posture", {"--kp-scale", "1e308"}, "[0, 100]"},
      {"posture", {"--kd-scale", "-1"}, "[0, 100]"},
      {"posture", {"--ramp", "1e9"}, "[0, 600] s"},
      {"balance", {"--support-margin", "1e308"}, "[0, 0.2] m"},
      {"balance", {"--ankle-damping", "1e308"}, "[0, 10000] N m s/rad"},
      {"balance", {"--z-damping", "1e300"}, "[0, 1e+07] N s/m"},
      {"playback", {"--time-scale", "1e-300", "--angles", std::string(OHRP_SOURCE_DIR) +
                                                              "/scenarios/stand.yaml"},
       "[0.001, 1000]"},
      {"track_ball", {"--max-rate", "1e308"}, "[0, 100] rad/s"},
      {"track_ball", {"--ki", "1e308"}, "[0, 10000] 1/s^2"},
      {"walk", {"--read-timeout", "1e308"}, "[0.001, 3600] s"},
  };
  for (const Refused& c : cases) {
    std::vector<std::string> args = {"--segment", kNoSegment};
    args.insert(args.end(), c.args.begin(), c.args.end());
    std::string out;
    EXPECT_EQ(RunProgram(c.program, args, &out), kExitUsage) << c.program << " " << c.args[0] << ": " << out;
    EXPECT_NE(out.find(c.args[0]), std::string::npos) << out;
    EXPECT_NE(out.find(c.expect), std::string::npos) << c.program << " " << c.args[0] << ": " << out;
    EXPECT_NE(out.find("plausible range"), std::string::npos) << out;
  }
}

TEST(ControllerOptions, TheRobotNarrowsTheRangeBeforeAttaching) {
  std::string out;
  // HRP-1S's soles: a margin of 0.1 m inside them leaves no support (plausible, not for it)
  EXPECT_EQ(RunProgram("balance", {"--segment", kNoSegment, "--support-margin", "0.1"}, &out), kExitUsage)
      << out;
  EXPECT_NE(out.find("this robot's range [0, 0.0"), std::string::npos) << out;
  // a stride of 1.2 m (plausible) is longer than HRP-1S's leg
  EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "--max-stride", "1.2", "-c", "goal 1 0 0"}, &out),
            kExitUsage)
      << out;
  EXPECT_NE(out.find("--max-stride (max_forward) = 1.2 m is beyond this robot's range"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("leg length"), std::string::npos) << out;
  EXPECT_EQ(out.find("cannot attach"), std::string::npos) << out;  // refused before attaching
  // within the leg's reach, but a swing faster than the hip can drive: 0.3 m strides at 0.5 s
  // steps swing the foot 0.6 m in 0.4 s, beyond what 400 N m moves through HRP-1S's 15 kg m^2
  EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "--max-stride", "0.3", "--step-time", "0.5",
                                "-c", "goal 1 0 0"}, &out),
            kExitUsage)
      << out;
  EXPECT_NE(out.find("swings the foot at up to"), std::string::npos) << out;
  EXPECT_NE(out.find("LLEG_HIP_P: 400 N m"), std::string::npos) << out;
  EXPECT_EQ(out.find("cannot attach"), std::string::npos) << out;
}

// a footstep file of one bad step (YAML, line 4 holds the step)
std::string StepsFile(const std::string& tag, const std::string& step) {
  return ohrp::testing::ScratchFile(
      tag, "frame: start\ndefaults: {height: 0.04, duration: 0.8}\nsteps:\n  - " + step + "\n",
      ".yaml");
}

TEST(ControllerOptions, FootstepFilesBeyondTheRobotsPhysicsAreRefusedBeforeAttaching) {
  struct Bad {
    std::string step, key, expect;
  };
  const std::vector<Bad> cases = {
      {"{foot: left, x: 0.1, y: 0.09, z: 1.0, yaw_deg: 0}", ": z: ", "m per step"},
      {"{foot: left, x: 0.1, y: 0.09, yaw_deg: 0, duration: 0.01}", ": duration: ",
       "out of the range 0.2"},
      {"{foot: left, x: 0.1, y: 0.09, yaw_deg: 0, height: 0.5}", ": height: ",
       "out of the range 0 .. 0.2"},
  };
  for (const Bad& b : cases) {
    const std::string file = StepsFile("steps", b.step);
    std::string out;
    EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "-c", "steps " + file}, &out), kExitUsage)
        << b.step << ": " << out;
    EXPECT_NE(out.find(file + ":4" + b.key), std::string::npos) << b.step << ": " << out;
    EXPECT_NE(out.find(b.expect), std::string::npos) << b.step << ": " << out;
    EXPECT_NE(out.find("from the model: leg length"), std::string::npos) << out;
    EXPECT_EQ(out.find("cannot attach"), std::string::npos) << out;
  }
  // the project's own stairs (0.1 m per stair) are within the limits: the walk gets as far as
  // attaching (no segment: exit 4)
  std::string out;
  EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "--params",
                         std::string(OHRP_SOURCE_DIR) + "/scenarios/steps/stairs_params.yaml", "-c",
                         "steps " + std::string(OHRP_SOURCE_DIR) + "/scenarios/steps/stairs_up.yaml"},
                &out),
            kExitAttach)
      << out;
}

TEST(ControllerOptions, WalkParameterFilesAreCheckedAgainstTheTableWithLineAndKey) {
  const std::string file = ohrp::testing::ScratchFile(
      "params", "step_time: 0.8\nmax_forward: 1e308\n", ".yaml");
  std::string out;
  EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "--params", file}, &out), kExitUsage) << out;
  EXPECT_NE(out.find(file + ":2: max_forward = 1e+308 is outside the plausible range [0, 1.5] m"),
            std::string::npos)
      << out;
}

TEST(ControllerOptions, ACappedSpeedIsSaidOnStderrAtOnce) {
  std::string out;
  EXPECT_EQ(RunProgram("walk", {"--segment", kNoSegment, "-c", "velocity 0.6 0 0 4"}, &out), kExitAttach)
      << out;
  EXPECT_NE(out.find("walk: note: \"velocity 0.6 0 0 4\": vx 0.600 m/s is beyond"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("walking at 0.3"), std::string::npos) << out;
}

}  // namespace
}  // namespace ohrp::controllers::testing
