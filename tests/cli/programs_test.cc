// Tests the command-line convention of every built program (cli/command_line.h): --help exits 0
// and names the exit codes; an unknown option, a missing required option, a value that is not a
// number (or not one of the choices) and a file that does not exist exit 2 with a short message
// naming what was wrong.
#include <gtest/gtest.h>

#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "../controllers/fake_robot.h"  // Spawn, WaitExit, Program, TempPath, ReadFile

namespace {

using ohrp::controllers::testing::Program;
using ohrp::testing::ReadFile;
using ohrp::controllers::testing::Spawn;
using ohrp::controllers::testing::TempPath;
using ohrp::controllers::testing::WaitExit;

const std::string kSource = OHRP_SOURCE_DIR;
const std::string kScene = kSource + "/mjcf/hrp1s/scene_flat.xml";

// one program and the arguments that make its command line valid
struct ProgramCase {
  std::string name;                 // in build/bin
  std::vector<std::string> valid;   // required arguments (all valid)
  std::string value_option;         // an option to give "abc": one that takes a number if any
  std::vector<std::string> missing_file;  // `valid` with a file that does not exist (empty: none)
  bool documents_exit_codes = true;  // --help has an "Exit codes" paragraph with "2 bad ..."
};

std::ostream& operator<<(std::ostream& os, const ProgramCase& c) { return os << c.name; }

// runs a program; its exit code, its stdout and stderr together in *output
int RunProgram(const std::string& name, std::vector<std::string> args, std::string* output) {
  const std::string log = TempPath("cli_" + name);
  args.insert(args.begin(), Program(name));
  const int code = WaitExit(Spawn(args, log), 20.0);
  *output = ReadFile(log);
  std::remove(log.c_str());
  return code;
}

std::vector<std::string> With(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

class ProgramCommandLine : public ::testing::TestWithParam<ProgramCase> {};

TEST_P(ProgramCommandLine, HelpExitsZeroAndNamesTheExitCodes) {
  const ProgramCase& c = GetParam();
  std::string out;
  EXPECT_EQ(RunProgram(c.name, {"--help"}, &out), 0) << out;
  if (c.documents_exit_codes) {
    EXPECT_NE(out.find("Exit codes"), std::string::npos) << out;
    EXPECT_TRUE(out.find("2 bad") != std::string::npos || out.find("2  bad") != std::string::npos)
        << out;
  }
}

TEST_P(ProgramCommandLine, UnknownOptionExitsTwo) {
  const ProgramCase& c = GetParam();
  std::string out;
  EXPECT_EQ(RunProgram(c.name, With(c.valid, {"--no-such-option"}), &out), 2) << out;
  EXPECT_NE(out.find("--no-such-option"), std::string::npos) << out;
}

TEST_P(ProgramCommandLine, MissingRequiredOptionExitsTwo) {
  const ProgramCase& c = GetParam();
  if (c.valid.empty()) GTEST_SKIP() << c.name << " has no required option";
  std::string out;
  EXPECT_EQ(RunProgram(c.name, {}, &out), 2) << out;
  EXPECT_NE(out.find("required"), std::string::npos) << out;
}

TEST_P(ProgramCommandLine, BadValueExitsTwoWithAShortMessage) {
  const ProgramCase& c = GetParam();
  std::string out;
  EXPECT_EQ(RunProgram(c.name, With(c.valid, {c.value_option, "abc"}), &out), 2) << out;
  EXPECT_NE(out.find(c.value_option), std::string::npos) << out;
  // one line and a pointer to --help, not a range of 300-digit numbers
  EXPECT_LT(out.size(), 200u) << out;
}

TEST_P(ProgramCommandLine, FileThatDoesNotExistExitsTwo) {
  const ProgramCase& c = GetParam();
  if (c.missing_file.empty()) GTEST_SKIP() << c.name << " checks no file on its command line";
  std::string out;
  EXPECT_EQ(RunProgram(c.name, c.missing_file, &out), 2) << out;
  EXPECT_NE(out.find("nosuch"), std::string::npos) << out;
}

// the options every controller shares (controllers/cli.h): a timeout that is not a time is a
// bad command line (exit 2), not a failed attach (4) or a wait without end
TEST(ControllerCommandLine, TimeoutsThatAreNotTimesExitTwo) {
  const std::string angles = kSource + "/scenarios/stand.yaml";  // any file that exists
  for (const std::vector<std::string>& valid :
       {std::vector<std::string>{"posture", "--segment", "x"},
        std::vector<std::string>{"playback", "--segment", "x", "--angles", angles},
        std::vector<std::string>{"balance", "--segment", "x"}}) {
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"--attach-timeout", "nan"},
          std::vector<std::string>{"--attach-timeout", "-1"},
          std::vector<std::string>{"--read-timeout", "-1"},
          std::vector<std::string>{"--read-timeout", "0"}}) {
      std::string out;
      const std::vector<std::string> args(valid.begin() + 1, valid.end());
      EXPECT_EQ(RunProgram(valid[0], With(args, bad), &out), 2) << valid[0] << " " << bad[0]
                                                               << " " << bad[1] << ": " << out;
      EXPECT_NE(out.find(bad[0]), std::string::npos) << out;
    }
  }
}

// every program of build/bin
const std::string kIo = "--io=" + Program("../lib/libohrp_io_replay.so");
const std::string kStand = kSource + "/scenarios/stand.yaml";
const std::string kSweep = kSource + "/tests/sweep/soles.yaml";
const std::string kAngles = kStand;  // any file that exists
const std::string kSample1 = kSource + "/../shared/external/openhrp3-sample/sample1.wrl";
INSTANTIATE_TEST_SUITE_P(
    Programs, ProgramCommandLine,
    ::testing::Values(
        ProgramCase{"sim_host", {"--scene", kScene}, "--control-period", {"--scene", "nosuch.xml"}},
        ProgramCase{"hw_driver", {"--model", kScene, kIo}, "--period",
                    {"--model", "nosuch.xml", kIo}},
        ProgramCase{"hw_emulator", {"--model", kScene}, "--period", {"--model", "nosuch.xml"}},
        ProgramCase{"ohrp_run", {kStand}, "--contact", {"nosuch.yaml"}},
        ProgramCase{"ohrp_video", {"runs/x"}, "--fps", {}},
        ProgramCase{"ohrp_view", {"runs/x"}, "--rate", {"runs/nosuch"}},
        ProgramCase{"ohrp_push", {}, "--max-impulse", {}},
        ProgramCase{"ohrp_sweep", {kSweep, "--check"}, "--jobs", {"nosuch.yaml"}},
        ProgramCase{"ohrp_vrml2mjcf", {kSample1}, "--print", {"nosuch.wrl"}},
        ProgramCase{"posture", {"--segment", "x"}, "--ramp",
                    {"--segment", "x", "--pose", "nosuch.yaml"}},
        ProgramCase{"track_ball", {"--segment", "x"}, "--kp",
                    {"--segment", "x", "--pose", "nosuch.yaml"}},
        ProgramCase{"playback", {"--segment", "x", "--angles", kAngles}, "--time-scale",
                    {"--segment", "x", "--angles", "nosuch.dat"}},
        ProgramCase{"balance", {"--segment", "x"}, "--lift",
                    {"--segment", "x", "--model", "nosuch.xml"}},
        ProgramCase{"walk", {"--segment", "x"}, "--step-time",
                    {"--segment", "x", "--params", "nosuch.yaml"}},
        ProgramCase{"reach", {"--segment", "x", "--goal-joints", "LARM_ELBOW=-1.0"}, "--clearance",
                    {"--segment", "x", "--goal-joints", "LARM_ELBOW=-1.0", "--collision-file",
                     "nosuch.yaml"}},
        ProgramCase{"excite", {"--segment", "x", "--joints", "LARM_ELBOW"}, "--amplitude", {}},
        ProgramCase{"bench_bridge", {}, "--cycles", {}, false},
        ProgramCase{"bench_loop", {}, "--duration", {}, false},
        ProgramCase{"bench_rt", {}, "--period", {}, false},
        ProgramCase{"bench_contact", {}, "--dt", {}, false},
        ProgramCase{"bench_effects", {}, "--cycles", {}, false},
        ProgramCase{"bench_cameras", {}, "--cycles", {}, false},
        ProgramCase{"bench_balance", {}, "--impulse", {}, false},
        ProgramCase{"bench_walk", {}, "--control-period", {}, false},
        ProgramCase{"bench_selfcollision", {}, "--postures", {"--file", "nosuch.yaml"}, false},
        ProgramCase{"bench_plan", {}, "--goals", {"--file", "nosuch.yaml"}, false},
        ProgramCase{"ohrp_selfcollision", {"--out", "/dev/null"}, "--margin",
                    {"--out", "/dev/null", "--model", "nosuch.xml"}, false},
        ProgramCase{"bench_accuracy", {}, "--restarts", {}, false},
        ProgramCase{"ohrp_compare_logs", {kStand, kStand}, "--max-lag", {"nosuch.csv", kStand}},
        ProgramCase{"ohrp_identify", {kStand}, "--window", {"nosuch.csv"}}),
    [](const ::testing::TestParamInfo<ProgramCase>& info) { return info.param.name; });

}  // namespace
