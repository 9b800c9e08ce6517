// Tests issue 28 item 6 for the tools: every numeric option of ohrp_video, the bench_*
// programs, bench_accuracy, ohrp_compare_logs, ohrp_identify, ohrp_view and ohrp_selfcollision
// refuses an absurd but finite value (1e308, -1e308, 1e-300, -1: each one outside the option's range)
// with exit 2 and one message naming the option and the range, before anything runs; a sensible
// value is accepted. The sensible value is given with --help: CLI11 checks every value before it
// prints the help, so this is fast and runs nothing, and a validator made with a quantity the
// table does not have (it refuses every value) fails here. Then the numbers the tools derive from
// options and files: a video's frame count, a bench's steps and cycles, a log's times and time
// grid, are checked before anything counts with them.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "../common/process.h"
#include "../common/scratch.h"
#include "cli/command_line.h"

namespace {

const std::string kSource = OHRP_SOURCE_DIR;
const std::string kStand = kSource + "/scenarios/stand.yaml";  // any file that exists
const std::string kScene = kSource + "/mjcf/hrp1s/scene_flat.xml";

// a program's exit code (-1: still running after `timeout` s, then killed); stdout and stderr in
// *output
int RunTool(const std::string& program, const std::vector<std::string>& args, std::string* output,
        double timeout = 10.0) {
  const std::string log = ohrp::testing::ScratchPath("out_" + program, ".txt");
  std::vector<std::string> argv = {std::string(OHRP_BIN_DIR) + "/" + program};
  argv.insert(argv.end(), args.begin(), args.end());
  const int code = ohrp::testing::WaitExit(ohrp::testing::Spawn(argv, ohrp::testing::ToFile(log)), timeout);
  *output = ohrp::testing::ReadFile(log);
  std::remove(log.c_str());
  return code;
}

// one numeric option of one program
struct OptionCase {
  std::string program;
  std::vector<std::string> valid;  // the program's required arguments
  std::string option;
  std::string sensible;            // a value the option takes
  std::string quantity;            // its row of the table ("": none, only the narrower range)
  double lo = NAN, hi = NAN;       // the program's own, narrower range (NaN: none)
};

std::ostream& operator<<(std::ostream& os, const OptionCase& c) {
  return os << c.program << " " << c.option;
}

// the range a refusal of `v` names: the table's when `v` is outside it, else the narrower one;
// "" when `v` is accepted
std::string ExpectedRange(const OptionCase& c, double v) {
  if (!c.quantity.empty()) {
    const ohrp::cli::PlausibleRange* r = ohrp::cli::FindPlausible(c.quantity);
    if (r == nullptr) return "the table's row '" + c.quantity + "'";  // fails the test: no such row
    if (!ohrp::cli::IsPlausible(*r, v)) {
      return "plausible range [" + ohrp::cli::detail::PlausibleNumber(r->lo) + ", " +
             ohrp::cli::detail::PlausibleNumber(r->hi) + "]";
    }
  }
  if (!std::isnan(c.lo) && (v < c.lo || v > c.hi)) {
    return "[" + ohrp::cli::detail::Short(c.lo) + ", " + ohrp::cli::detail::Short(c.hi) + "]";
  }
  return "";
}

class ToolOption : public ::testing::TestWithParam<OptionCase> {};

TEST_P(ToolOption, AbsurdValuesExitTwoNamingTheOptionAndTheRange) {
  const OptionCase& c = GetParam();
  int refused = 0;
  for (const char* text : {"1e308", "-1e308", "1e-300", "-1"}) {
    const std::string range = ExpectedRange(c, std::strtod(text, nullptr));
    if (range.empty()) continue;  // within the option's range (e.g. 1e-300 for an impulse)
    ++refused;
    std::vector<std::string> args = c.valid;
    args.insert(args.end(), {c.option, text});
    std::string out;
    EXPECT_EQ(RunTool(c.program, args, &out), 2) << c << " " << text << ": " << out;
    EXPECT_NE(out.find(c.option), std::string::npos) << c << " " << text << ": " << out;
    EXPECT_NE(out.find(range), std::string::npos) << c << " " << text << ": want '" << range
                                                  << "' in: " << out;
  }
  EXPECT_GE(refused, 2) << c << ": fewer than two of the absurd values are outside its range";
}

TEST_P(ToolOption, ASensibleValueIsAccepted) {
  const OptionCase& c = GetParam();
  ASSERT_EQ(ExpectedRange(c, std::strtod(c.sensible.c_str(), nullptr)), "") << c;
  std::vector<std::string> args = c.valid;
  args.insert(args.end(), {c.option, c.sensible, "--help"});
  std::string out;
  EXPECT_EQ(RunTool(c.program, args, &out), 0) << c << " " << c.sensible << ": " << out;
}

const std::vector<std::string> kCompare = {kStand, kStand};
const std::vector<std::string> kOut = {"--out", "/dev/null"};
constexpr double kNone = NAN;

INSTANTIATE_TEST_SUITE_P(
    Tools, ToolOption,
    ::testing::Values(
        // ohrp_video
        OptionCase{"ohrp_video", {"runs/x"}, "--fps", "30", "frame_rate"},
        OptionCase{"ohrp_video", {"runs/x"}, "--speed", "2", "speed_factor"},
        OptionCase{"ohrp_video", {"runs/x"}, "--from", "1.5", "time"},
        OptionCase{"ohrp_video", {"runs/x"}, "--until", "3", "time"},
        OptionCase{"ohrp_video", {"runs/x"}, "--still", "1,2.5", "time"},
        OptionCase{"ohrp_video", {"runs/x"}, "--width", "320", "pixels"},
        OptionCase{"ohrp_video", {"runs/x"}, "--height", "240", "pixels"},
        OptionCase{"ohrp_video", {"runs/x"}, "--distance", "4", "distance"},
        OptionCase{"ohrp_video", {"runs/x"}, "--azimuth", "90", "angle_deg"},
        OptionCase{"ohrp_video", {"runs/x"}, "--elevation", "-20", "angle_deg"},
        // the benchmarks
        OptionCase{"bench_contact", {}, "--dt", "0.002", "physics_dt"},
        OptionCase{"bench_contact", {}, "--steps", "100", "steps"},
        OptionCase{"bench_contact", {}, "--repeats", "3", "repeats"},
        OptionCase{"bench_loop", {}, "--dt", "0.002", "physics_dt"},
        OptionCase{"bench_loop", {}, "--duration", "1", "duration"},
        OptionCase{"bench_loop", {}, "--repeats", "3", "repeats"},
        OptionCase{"bench_rt", {}, "--duration", "1", "duration"},
        OptionCase{"bench_rt", {}, "--rounds", "10", "repeats"},
        OptionCase{"bench_rt", {}, "--period", "0.002", "control_period"},
        OptionCase{"bench_rt", {}, "--priority", "50", "priority"},
        OptionCase{"bench_bridge", {}, "--cycles", "1000", "cycles"},
        OptionCase{"bench_bridge", {}, "--warmup", "100", "count"},
        OptionCase{"bench_cameras", {}, "--cycles", "10", "cycles"},
        OptionCase{"bench_cameras", {}, "--repeats", "2", "repeats"},
        OptionCase{"bench_effects", {}, "--cycles", "100", "cycles"},
        OptionCase{"bench_effects", {}, "--repeats", "2", "repeats"},
        OptionCase{"bench_balance", {}, "--rounds", "5", "repeats", 1, 1000},
        OptionCase{"bench_balance", {}, "--cycles", "100", "cycles", 10, 100000},
        OptionCase{"bench_balance", {}, "--impulse", "10", "impulse", 0, 60},
        OptionCase{"bench_walk", {}, "--control-period", "0.005", "control_period", 0.001, 0.02},
        OptionCase{"bench_selfcollision", {}, "--postures", "1000", "count", 100, 10000000},
        OptionCase{"bench_selfcollision", {}, "--control-period", "0.005", "control_period"},
        OptionCase{"bench_accuracy", {}, "--restarts", "3", "repeats"},
        OptionCase{"bench_accuracy", {}, "--piece-windows", "4", "repeats"},
        // ohrp_compare_logs, ohrp_identify
        OptionCase{"ohrp_compare_logs", kCompare, "--from", "0.5", "time"},
        OptionCase{"ohrp_compare_logs", kCompare, "--to", "2", "time"},
        OptionCase{"ohrp_compare_logs", kCompare, "--max-lag", "1", "duration"},
        OptionCase{"ohrp_identify", {kStand}, "--settle", "0.2", "wait"},
        OptionCase{"ohrp_identify", {kStand}, "--window", "2", "duration"},
        OptionCase{"ohrp_identify", {kStand}, "--step", "0.1", "fraction", 0.01, 0.5},
        // ohrp_view
        OptionCase{"ohrp_view", {"runs/x"}, "--port", "8080", "port"},
        OptionCase{"ohrp_view", {"runs/x"}, "--rate", "20", "frame_rate"},
        OptionCase{"ohrp_view", {"runs/x"}, "--image-rate", "5", "frame_rate", 1, 30},
        OptionCase{"ohrp_view", {"runs/x"}, "--attach-timeout", "5", "wait"},
        // ohrp_selfcollision
        OptionCase{"ohrp_selfcollision", kOut, "--margin", "0.02", "clearance"},
        OptionCase{"ohrp_selfcollision", kOut, "--clearance", "0.01", "clearance"},
        OptionCase{"ohrp_selfcollision", kOut, "--samples", "1000", "count", 1, 100000000},
        OptionCase{"ohrp_selfcollision", kOut, "--coarse", "8", "count", 2, 1000},
        OptionCase{"ohrp_selfcollision", kOut, "--fine", "4", "count", 1, 1000},
        OptionCase{"ohrp_selfcollision", kOut, "--cell-samples", "16", "count", 2, 1000000},
        OptionCase{"ohrp_selfcollision", kOut, "--verify", "1000", "count", 0, 100000000},
        OptionCase{"ohrp_selfcollision", kOut, "--proof-budget", "5000", "count", 1, 100000000},
        OptionCase{"ohrp_selfcollision", kOut, "--min-range-share", "0.3", "fraction"},
        OptionCase{"ohrp_selfcollision", kOut, "--seed", "7", "", 0, 18446744073709551615.0}),
    [](const ::testing::TestParamInfo<OptionCase>& info) {
      std::string name = info.param.program + "_";
      for (char ch : info.param.option)
        if (std::isalnum(static_cast<unsigned char>(ch))) name += ch;
      return name;
    });

// ---- numbers derived from options and files

// a data log of HRP-1S (time and one joint) with these times, in the scratch folder
std::string LogWithTimes(const std::vector<std::string>& times) {
  std::string text = "time,q_WAIST_P\n";
  for (size_t i = 0; i < times.size(); ++i) text += times[i] + "," + std::to_string(0.01 * i) + "\n";
  return ohrp::testing::ScratchFile("log", text, ".csv");
}

// a video of 1e6 s at 0.001x and 240 fps would have 2.4e11 frames: refused with the frame
// count's range, not "-2147483647 frames" and exit 0
TEST(DerivedNumbers, VideoFrameCountOutsideItsRangeIsRefused) {
  const std::string log = LogWithTimes({"0", "1000000"});
  std::string out;
  EXPECT_EQ(RunTool("ohrp_video", {log, "--scene", kScene, "--speed", "0.001", "--fps", "240",
                               "--frames", ohrp::testing::ScratchFolder("frames")},
                &out),
            2)
      << out;
  EXPECT_NE(out.find("frame count"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [1, 1e+07]"), std::string::npos) << out;
}

// a log time of 1e300 (a number of the file) is refused with its row and the time's range
TEST(DerivedNumbers, VideoLogTimeOutsideItsRangeIsRefused) {
  const std::string log = LogWithTimes({"0", "1", "1e300"});
  std::string out;
  EXPECT_EQ(RunTool("ohrp_video", {log, "--scene", kScene, "--frames", ohrp::testing::ScratchFolder("frames")},
                &out),
            2)
      << out;
  EXPECT_NE(out.find("time, row 3 = 1e+300"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [-1e+06, 1e+06]"), std::string::npos) << out;
}

// 1e6 s of 0.1 ms steps is 1e10 steps, more than an int holds: refused before anything runs
TEST(DerivedNumbers, BenchLoopStepsOutsideTheirRangeAreRefused) {
  std::string out;
  EXPECT_EQ(RunTool("bench_loop", {"--duration", "1000000", "--dt", "0.0001"}, &out), 2) << out;
  EXPECT_NE(out.find("--duration / --dt = 1e+10"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [1, 1e+09]"), std::string::npos) << out;
}

// 1 s over a million rounds is less than one 1 ms cycle a round: refused, not a million empty
// driver runs
TEST(DerivedNumbers, BenchRtRoundsWithoutACycleAreRefused) {
  std::string out;
  EXPECT_EQ(RunTool("bench_rt", {"--duration", "1", "--rounds", "1000000", "--period", "0.001"}, &out), 2)
      << out;
  EXPECT_NE(out.find("the cycles of a round"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [1, 1e+09]"), std::string::npos) << out;
}

// logs sampled at 1 us whose last row is 1000 s later: a cross-correlation grid of 1e9 samples
// (8 GB) is refused with the samples' range instead of being made
TEST(DerivedNumbers, CompareTimeGridOutsideItsRangeIsRefused) {
  std::vector<std::string> times;
  for (int i = 0; i < 20; ++i) times.push_back(std::to_string(i) + "e-6");
  times.push_back("1000");
  const std::string a = LogWithTimes(times), b = LogWithTimes(times);
  std::string out;
  EXPECT_EQ(RunTool("ohrp_compare_logs", {a, b, "--align", "xcorr:q_WAIST_P", "--no-plot", "--out",
                                      ohrp::testing::ScratchFolder("compare")},
                &out),
            2)
      << out;
  EXPECT_NE(out.find("time grid"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [2, 1e+08]"), std::string::npos) << out;
}

// a log time of 1e300 in a compared log: refused with its row and the time's range
TEST(DerivedNumbers, CompareLogTimeOutsideItsRangeIsRefused) {
  const std::string a = LogWithTimes({"0", "0.1", "0.2", "0.3"});
  const std::string b = LogWithTimes({"0", "0.1", "0.2", "1e300"});
  std::string out;
  EXPECT_EQ(RunTool("ohrp_compare_logs", {a, b, "--align", "none", "--no-plot", "--out",
                                      ohrp::testing::ScratchFolder("compare")},
                &out),
            2)
      << out;
  EXPECT_NE(out.find("time, row 4 = 1e+300"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [-1e+06, 1e+06]"), std::string::npos) << out;
}

// OpenHRP's box.wrl with one number replaced: `from` (its first place after the robot's
// DEF WAIST Joint, not in the PROTOs' defaults) by `to`
std::string BoxWith(const std::string& from, const std::string& to) {
  std::string text = ohrp::testing::ReadFile(kSource + "/../shared/external/openhrp3-sample/box.wrl");
  const size_t at = text.find(from, text.find("DEF WAIST Joint"));
  if (at == std::string::npos) return "";
  text.replace(at, from.size(), to);
  return ohrp::testing::ScratchFile("box", text, ".wrl");
}

// the numbers of a VRML file: a segment of 1e300 kg, a box 1e300 m wide and a joint 1e300 m
// away are refused with the file's line, the field and the range, not converted (on today's
// main ohrp_vrml2mjcf prints "1e+300 kg" and exits 0)
TEST(FileNumbers, VrmlNumbersOutsideTheirRangesAreRefused) {
  struct Case {
    std::string from, to, field, range;
  };
  for (const Case& c : {Case{"mass 0.5", "mass 1e300", "mass of Segment BODY", "[0.001, 10000] kg"},
                        Case{"size 0.2 0.8 0.2", "size 0.2 1e300 0.2", "Box size", "[0, 1000] m"},
                        Case{"translation 0 0 0", "translation 0 0 -1e300", "translation", "[0, 1000] m"}}) {
    const std::string wrl = BoxWith(c.from, c.to);
    ASSERT_FALSE(wrl.empty()) << "no '" << c.from << "' in box.wrl";
    std::string out;
    EXPECT_EQ(RunTool("ohrp_vrml2mjcf", {wrl, "--print", "summary"}, &out), 2) << c.to << ": " << out;
    EXPECT_NE(out.find(c.field), std::string::npos) << c.to << ": " << out;
    EXPECT_NE(out.find("plausible range " + c.range), std::string::npos) << c.to << ": " << out;
    EXPECT_NE(out.find(".wrl:"), std::string::npos) << c.to << ": the file's line: " << out;
  }
  // the file itself converts
  std::string out;
  EXPECT_EQ(RunTool("ohrp_vrml2mjcf", {BoxWith("mass 0.5", "mass 0.5"), "--print", "summary"}, &out), 0)
      << out;
}

// a hinge's limit of -1000 rad in the model ohrp_selfcollision pre-processes: refused with the
// joint and the range of an angle, not cut into cells of 80 rad (on today's main it runs)
TEST(FileNumbers, SelfCollisionHingeLimitOutsideItsRangeIsRefused) {
  std::string xml = ohrp::testing::ReadFile(kSource + "/mjcf/hrp1s/hrp1s.xml");
  const std::string from = "range=\"-0.5236 1.0472\"";
  const size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos) << "WAIST_P's range is not in hrp1s.xml";
  xml.replace(at, from.size(), "range=\"-1000 1.0472\"");
  const std::string model = ohrp::testing::ScratchFile("absurd", xml, ".xml");
  std::string out;
  EXPECT_EQ(RunTool("ohrp_selfcollision", {"--model", model, "--out", ohrp::testing::ScratchPath("sc", ".yaml"),
                                           "--quiet"},
                    &out),
            2)
      << out;
  EXPECT_NE(out.find("joint WAIST_P limit = -1000"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [-7, 7] rad"), std::string::npos) << out;
}

// the reference posture's angle of 1000 rad (a keyframe of the model): refused the same way
TEST(FileNumbers, SelfCollisionReferenceAngleOutsideItsRangeIsRefused) {
  std::string xml = ohrp::testing::ReadFile(kSource + "/mjcf/hrp1s/hrp1s.xml");
  const std::string from = "qpos=\"0 0 0.683880068 1 0 0 0 0 ";  // halfsit, WAIST_P first
  const size_t at = xml.find(from);
  ASSERT_NE(at, std::string::npos) << "halfsit's qpos is not in hrp1s.xml";
  xml.replace(at, from.size(), "qpos=\"0 0 0.683880068 1 0 0 0 1000 ");
  const std::string model = ohrp::testing::ScratchFile("absurd_key", xml, ".xml");
  std::string out;
  EXPECT_EQ(RunTool("ohrp_selfcollision", {"--model", model, "--out", ohrp::testing::ScratchPath("sc", ".yaml"),
                                           "--reference", "halfsit", "--quiet"},
                    &out),
            2)
      << out;
  EXPECT_NE(out.find("keyframe halfsit: joint WAIST_P = 1000"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [-7, 7] rad"), std::string::npos) << out;
}

// a log time of 1e300 in a run replayed by ohrp_view or measured by ohrp_identify: refused with
// its row and the time's range before anything is served or simulated
TEST(DerivedNumbers, ViewAndIdentifyLogTimeOutsideItsRangeIsRefused) {
  const std::string run = ohrp::testing::ScratchFolder("run");
  const std::string log = run + "/log.csv";
  {
    std::ofstream f(log);
    f << "time,q_WAIST_P\n0,0\n0.1,0.01\n0.2,0.02\n1e300,0.03\n";
  }
  std::string out;
  EXPECT_EQ(RunTool("ohrp_view", {run, "--scene", kScene, "--port", "0"}, &out), 2) << out;
  EXPECT_NE(out.find("time, row 4 = 1e+300"), std::string::npos) << out;
  EXPECT_NE(out.find("plausible range [-1e+06, 1e+06]"), std::string::npos) << out;
  EXPECT_EQ(RunTool("ohrp_identify", {log, "--channel", "q_WAIST_P", "--out",
                                      ohrp::testing::ScratchFolder("identify"), "--quiet"},
                    &out),
            2)
      << out;
  EXPECT_NE(out.find("time, row 4 = 1e+300"), std::string::npos) << out;
}

}  // namespace
