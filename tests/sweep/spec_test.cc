// Tests sweep files (tools/sweep/src/spec.cc): the variants a grid, a zip group and ranges give,
// keys set by path in the scenario, and every variant's scenario read back by the runner.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>

#include "runner/scenario.h"
#include "sweep/sweep.h"

namespace ohrp::sweep {
namespace {

const std::string kSource = OHRP_SOURCE_DIR;
// a sweep "file" beside the tests' scenario, so that `scenario: stand_short.yaml` resolves
const std::string kPath = kSource + "/tests/sweep/in_memory.yaml";

SweepSpec Parse(const std::string& text) {
  SweepSpec s;
  std::string error;
  EXPECT_TRUE(ParseSweep(text, kPath, kSource, &s, &error)) << error;
  return s;
}

std::string Refusal(const std::string& text) {
  SweepSpec s;
  std::string error;
  EXPECT_FALSE(ParseSweep(text, kPath, kSource, &s, &error)) << text;
  return error;
}

// the value of parameter `key` in variant `v`
std::string ValueOf(const SweepSpec& s, int v, const std::string& key) {
  for (size_t p = 0; p < s.parameters.size(); ++p)
    if (s.parameters[p].key == key) return s.parameters[p].values[s.variants[v].value_index[p]].text;
  return "?";
}

TEST(SweepSpec, GridIsTheCartesianProductFirstAxisSlowest) {
  const auto s = Parse(
      "scenario: stand_short.yaml\n"
      "parameters:\n"
      "  - {key: contact_params.stiffness, values: [1e6, 2e6]}\n"
      "  - {key: contact_params.damping, values: [10, 20, 30]}\n");
  ASSERT_EQ(s.variants.size(), 6u);
  const char* expected[6][2] = {{"1000000", "10"}, {"1000000", "20"}, {"1000000", "30"},
                                {"2000000", "10"}, {"2000000", "20"}, {"2000000", "30"}};
  for (int v = 0; v < 6; ++v) {
    EXPECT_EQ(ValueOf(s, v, "contact_params.stiffness"), expected[v][0]) << v;
    EXPECT_EQ(ValueOf(s, v, "contact_params.damping"), expected[v][1]) << v;
    // the runner reads the variant's scenario with these values
    runner::Scenario scenario;
    std::string error;
    ASSERT_TRUE(runner::ParseScenario(s.variant_scenarios[v], "variant", &scenario, &error)) << error;
    EXPECT_EQ(scenario.contact_params.at("stiffness"), std::atof(expected[v][0]));
    EXPECT_EQ(scenario.contact_params.at("damping"), std::atof(expected[v][1]));
    // the rest of the scenario is untouched
    EXPECT_EQ(scenario.duration, 1.5);
    EXPECT_EQ(scenario.keyframe, "halfsit");
    ASSERT_EQ(scenario.checks.size(), 3u);
  }
  // the default time limit is ohrp_run's: 60 s + 30 x the duration
  EXPECT_DOUBLE_EQ(s.time_limit, 60 + 30 * 1.5);
}

TEST(SweepSpec, ZipGroupVariesItsParametersTogether) {
  const auto s = Parse(
      "scenario: stand_short.yaml\n"
      "time_limit: 20\n"
      "parameters:\n"
      "  - zip:\n"
      "      - {key: physics_dt, values: [0.001, 0.0005]}\n"
      "      - {key: control_period, values: [0.005, 0.002]}\n"
      "  - {key: integrator, values: [euler, implicit]}\n");
  ASSERT_EQ(s.variants.size(), 4u);
  EXPECT_EQ(ValueOf(s, 1, "physics_dt"), "0.001");
  EXPECT_EQ(ValueOf(s, 1, "control_period"), "0.005");
  EXPECT_EQ(ValueOf(s, 1, "integrator"), "implicit");
  EXPECT_EQ(ValueOf(s, 2, "physics_dt"), "0.0005");
  EXPECT_EQ(ValueOf(s, 2, "control_period"), "0.002");
  EXPECT_EQ(ValueOf(s, 2, "integrator"), "euler");
  runner::Scenario scenario;
  std::string error;
  ASSERT_TRUE(runner::ParseScenario(s.variant_scenarios[3], "variant", &scenario, &error)) << error;
  EXPECT_EQ(scenario.physics_dt, 0.0005);
  EXPECT_EQ(scenario.integrator, "implicit");
  EXPECT_EQ(s.time_limit, 20);
}

TEST(SweepSpec, RangesAreLinearOrGeometric) {
  const auto s = Parse(
      "scenario: stand_short.yaml\n"
      "parameters:\n"
      "  - {key: contact_params.stiffness, range: {from: 1e5, to: 1e8, steps: 4, scale: log}}\n"
      "  - {key: contact_params.damping, range: {from: 10, to: 40, steps: 4}}\n");
  ASSERT_EQ(s.parameters.size(), 2u);
  const double geometric[4] = {1e5, 1e6, 1e7, 1e8}, linear[4] = {10, 20, 30, 40};
  for (int i = 0; i < 4; ++i) {
    // log steps: from x (to/from)^(i/(n-1)), to within rounding of exp/log
    EXPECT_NEAR(s.parameters[0].values[i].number, geometric[i], 1e-12 * geometric[i]) << i;
    EXPECT_EQ(s.parameters[1].values[i].number, linear[i]) << i;
  }
  EXPECT_TRUE(s.parameters[0].log_scale);
  EXPECT_FALSE(s.parameters[1].log_scale);
  EXPECT_EQ(s.parameters[0].values[3].number, 1e8);  // the end exactly
  EXPECT_EQ(s.variants.size(), 16u);
}

TEST(SweepSpec, SetKeyReachesListItemsAndCreatesMappings) {
  const std::string yaml = "a: 1\nlist:\n  - {x: 1, y: [5, 6]}\n";
  std::string out, why;
  Value v{"7", true, 7};
  ASSERT_TRUE(SetKey(yaml, "list[0].y[1]", v, &out, &why)) << why;
  ASSERT_TRUE(SetKey(out, "b.c", Value{"text", false, 0}, &out, &why)) << why;
  EXPECT_NE(out.find("c: text"), std::string::npos) << out;
  EXPECT_NE(out.find("7"), std::string::npos) << out;
  EXPECT_EQ(out.find("6"), std::string::npos) << out;
  EXPECT_FALSE(SetKey(yaml, "list[3].x", v, &out, &why));
  EXPECT_NE(why.find("no item [3]"), std::string::npos) << why;
  EXPECT_FALSE(SetKey(yaml, "a.b", v, &out, &why));  // under a number
  EXPECT_FALSE(SetKey(yaml, "list[x]", v, &out, &why));
  EXPECT_FALSE(SetKey(yaml, "a..b", v, &out, &why));
}

TEST(SweepSpec, NumbersAreWrittenShortestAndExact) {
  for (double x : {3e6, 0.1, 1.0 / 3.0, 2.5e-4, 45.0, 1e-300})
    EXPECT_EQ(std::strtod(NumberText(x).c_str(), nullptr), x) << NumberText(x);
  EXPECT_EQ(NumberText(3e6), "3000000");
  EXPECT_EQ(NumberText(0.1), "0.1");
}

TEST(SweepSpec, RefusalsNameTheLineAndTheKey) {
  EXPECT_NE(Refusal("scenario: stand_short.yaml\nparameters: []\n").find("'parameters' must be a non-empty list"),
            std::string::npos);
  EXPECT_NE(Refusal("parameters:\n  - {key: duration, values: [1]}\n").find("'scenario' is required"),
            std::string::npos);
  const std::string e = Refusal(
      "scenario: stand_short.yaml\n"
      "parameters:\n"
      "  - {key: duration, values: [1.5, 0.5]}\n");  // 0.5 s: before the checks' `after: 1.0`
  EXPECT_NE(e.find("sweep '" + kPath + "': line 3: duration = 0.5: variant v001"), std::string::npos) << e;
  EXPECT_NE(e.find("checks"), std::string::npos) << e;
  EXPECT_NE(Refusal("scenario: stand_short.yaml\nparameters:\n  - {key: integrator, values: [verlet]}\n")
                .find("integrator: must be euler, rk4 or implicit"),
            std::string::npos);
}

}  // namespace
}  // namespace ohrp::sweep
