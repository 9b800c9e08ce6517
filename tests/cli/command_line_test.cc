// Tests cli/command_line.h: the number checks' messages and ParseCommandLine's exit codes.
#include "cli/command_line.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace {

// what the validator says about `text` ("" when accepted)
std::string Check(const CLI::Validator& v, std::string text) { return v(text); }

TEST(NumberChecks, PositiveAcceptsPositiveNumbersOnly) {
  EXPECT_EQ(Check(ohrp::cli::Positive(), "0.005"), "");
  EXPECT_EQ(Check(ohrp::cli::Positive(), "1e3"), "");
  EXPECT_EQ(Check(ohrp::cli::Positive(), "0"), "0 is out of range (want a number > 0)");
  EXPECT_EQ(Check(ohrp::cli::Positive(), "-1"), "-1 is out of range (want a number > 0)");
  for (const char* bad : {"abc", "nan", "inf", "1e999", "5x", ""})
    EXPECT_EQ(Check(ohrp::cli::Positive(), bad),
              std::string("'") + bad + "' is not a number (want a number > 0)");
}

TEST(NumberChecks, NonNegativeAcceptsZero) {
  EXPECT_EQ(Check(ohrp::cli::NonNegative(), "0"), "");
  EXPECT_EQ(Check(ohrp::cli::NonNegative(), "-0.1"), "-0.1 is out of range (want a number >= 0)");
  EXPECT_EQ(Check(ohrp::cli::NonNegative(), "nan"), "'nan' is not a number (want a number >= 0)");
}

TEST(NumberChecks, InRangeNamesItsBoundsShortly) {
  const CLI::Validator v = ohrp::cli::InRange(1e-4, 1.0);
  EXPECT_EQ(Check(v, "0.0001"), "");
  EXPECT_EQ(Check(v, "1"), "");
  EXPECT_EQ(Check(v, "2"), "2 is out of range (want a number in [0.0001, 1])");
  EXPECT_EQ(Check(v, "abc"), "'abc' is not a number (want a number in [0.0001, 1])");
}

// ParseCommandLine on an app with one required number
int Parse(std::vector<std::string> args, double* period) {
  CLI::App app{"test"};
  app.add_option("--period", *period)->required()->check(ohrp::cli::Positive());
  args.insert(args.begin(), "/some/folder/prog");
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  return ohrp::cli::ParseCommandLine(&app, static_cast<int>(argv.size()), argv.data());
}

TEST(ParseCommandLine, GoesOnWithAValidLine) {
  double period = 0;
  EXPECT_EQ(Parse({"--period", "0.01"}, &period), -1);
  EXPECT_DOUBLE_EQ(period, 0.01);
}

TEST(ParseCommandLine, HelpIsZeroAndEveryErrorIsTwo) {
  double period = 0;
  testing::internal::CaptureStdout();
  EXPECT_EQ(Parse({"--help"}, &period), ohrp::cli::kExitHelp);
  EXPECT_NE(testing::internal::GetCapturedStdout().find("--period"), std::string::npos);
  for (const auto& args : std::vector<std::vector<std::string>>{
           {}, {"--period", "abc"}, {"--period", "0"}, {"--period", "1", "--other"},
           {"--period", "1", "extra"}, {"--period"}}) {
    testing::internal::CaptureStderr();
    EXPECT_EQ(Parse(args, &period), ohrp::cli::kExitUsage) << args.size();
    const std::string err = testing::internal::GetCapturedStderr();
    // the program's name without its folder, then CLI11's text, then a pointer to --help
    EXPECT_EQ(err.rfind("prog: ", 0), 0u) << err;
    EXPECT_NE(err.find("Run with --help"), std::string::npos) << err;
  }
}

}  // namespace

namespace {

TEST(Plausible, EveryRangeIsOrderedFiniteAndExplained) {
  for (const ohrp::cli::PlausibleRange& r : ohrp::cli::kPlausibleRanges) {
    EXPECT_TRUE(std::isfinite(r.lo) && std::isfinite(r.hi) && r.lo < r.hi) << r.quantity;
    EXPECT_NE(std::string(r.why), "") << r.quantity;
    EXPECT_EQ(ohrp::cli::FindPlausible(r.quantity), &r) << r.quantity << " named twice";
  }
}

TEST(Plausible, RefusesAbsurdButFiniteValuesNamingRangeAndUnit) {
  EXPECT_EQ(ohrp::cli::CheckPlausible("physics_dt", 0.001, "physics_dt"), "");
  EXPECT_EQ(ohrp::cli::CheckPlausible("physics_dt", 1e-300, "s.yaml:3: physics_dt"),
            "s.yaml:3: physics_dt = 1e-300 is outside the plausible range [1e-05, 0.02] s "
            "(an integration step between 10 us and 20 ms)");
  for (double bad : {1e308, -1.0, std::nan(""), HUGE_VAL})
    EXPECT_NE(ohrp::cli::CheckPlausible("gain_scale", bad, "--kp-scale"), "") << bad;
  EXPECT_EQ(ohrp::cli::CheckPlausible("gain_scale", 0, "--kp-scale"), "");  // bounds inclusive
  EXPECT_EQ(ohrp::cli::CheckPlausible("gain_scale", 100, "--kp-scale"), "");
  EXPECT_EQ(ohrp::cli::CheckPlausible("no_such_quantity", 1, "x"),
            "x: no plausible range for the quantity 'no_such_quantity'");
}

// a column of a file (a log's times): the first value outside the range, named by its row
TEST(Plausible, EachValueOfAColumnIsCheckedAndTheRowNamed) {
  const std::vector<double> times = {0, 0.5, 1e300, -1e300};
  EXPECT_EQ(ohrp::cli::CheckPlausibleEach("time", times, "log.csv: time"),
            "log.csv: time, row 3 = 1e+300 is outside the plausible range [-1e+06, 1e+06] s (a time "
            "within about 11 days of a run's start)");
  EXPECT_EQ(ohrp::cli::CheckPlausibleEach("time", std::vector<double>{0, 1, 2}, "t"), "");
  EXPECT_NE(ohrp::cli::CheckPlausibleEach("time", std::vector<double>{0, std::nan("")}, "t"), "");
  EXPECT_EQ(ohrp::cli::CheckPlausibleEach("no_such_quantity", std::vector<double>{1}, "t"),
            "t, row 1: no plausible range for the quantity 'no_such_quantity'");
}

TEST(Plausible, ValidatorSaysTheRange) {
  const CLI::Validator v = ohrp::cli::Plausible("speed_factor");
  EXPECT_EQ(Check(v, "1"), "");
  EXPECT_EQ(Check(v, "1e-300"),
            "1e-300 is outside the plausible range [0.001, 1000] (a playback or video speed "
            "between 0.001x and 1000x)");
  EXPECT_EQ(Check(v, "abc"), "'abc' is not a number");
  EXPECT_EQ(Check(ohrp::cli::Plausible("nonexistent"), "1"),
            "1: no plausible range for the quantity 'nonexistent'");
}

}  // namespace
