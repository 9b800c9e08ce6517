// Tests the scenario parser's refusals (tools/runner/src/scenario.cc, check_keys.cc): every
// bad key or value is refused with the file, the line and the key before anything runs, a
// scenario without checks or controllers is refused, and every shipped scenario still loads.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "runner/check_keys.h"
#include "runner/recovery.h"
#include "runner/scenario.h"
#include "temp_file.h"

namespace ohrp::runner {
namespace {

namespace fs = std::filesystem;

// a valid scenario; the cases below replace or add lines
const std::vector<std::string> kValid = {
    "scene: mjcf/hrp1s/scene_flat.xml",                    // line 1
    "duration: 2",                                         // line 2
    "physics_dt: 0.001",                                   // line 3
    "control_period: 0.005",                               // line 4
    "controllers:",                                        // line 5
    "  - {program: posture, args: [--ramp, \"1.0\"]}",     // line 6
    "checks:",                                             // line 7
    "  - {type: not_fallen, min_height: 0.5}",             // line 8
};

// the valid scenario with line `line` (1-based) replaced by `text` (several lines allowed;
// "" removes it), or with `text` appended when `line` is 0
std::string Variant(int line, const std::string& text) {
  std::string out;
  for (size_t i = 0; i < kValid.size(); ++i) {
    if (static_cast<int>(i) + 1 == line) {
      if (!text.empty()) out += text + "\n";
    } else {
      out += kValid[i] + "\n";
    }
  }
  if (line == 0) out += text + "\n";
  return out;
}

struct Case {
  std::string text;      // the scenario file
  std::string expected;  // a part of the message, from "line N: " on
};

void ExpectRefused(const std::vector<Case>& cases) {
  for (const auto& c : cases) {
    const std::string path = Temp(c.text);
    Scenario s;
    std::string error;
    EXPECT_FALSE(LoadScenario(path, &s, &error)) << c.text;
    EXPECT_NE(error.find("scenario '" + path + "'"), std::string::npos) << error;
    EXPECT_NE(error.find(c.expected), std::string::npos)
        << "expected: " << c.expected << "\ngot: " << error << "\nfor:\n" << c.text;
  }
}

TEST(ScenarioStrict, TheValidBaseLoads) {
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(Temp(Variant(0, "")), &s, &error)) << error;
  EXPECT_EQ(s.controllers.size(), 1u);
  EXPECT_EQ(s.controllers[0].line, 6);
  EXPECT_EQ(s.scene_line, 1);
  ASSERT_EQ(s.checks.size(), 1u);
  EXPECT_EQ(s.checks[0].Number("min_height", 0), 0.5);
}

// the text entry point (the fuzzer's) reads what the file entry point reads, and refuses alike
TEST(ScenarioStrict, ParseScenarioFromTextMatchesTheFile) {
  Scenario from_text;
  std::string error;
  ASSERT_TRUE(ParseScenario(Variant(0, ""), "dir/base.yaml", &from_text, &error)) << error;
  EXPECT_EQ(from_text.name, "base");
  EXPECT_EQ(from_text.file, "dir/base.yaml");
  EXPECT_EQ(from_text.controllers.size(), 1u);
  EXPECT_EQ(from_text.checks.size(), 1u);
  EXPECT_FALSE(ParseScenario(Variant(3, "physics_dt: -1"), "text.yaml", &from_text, &error));
  EXPECT_NE(error.find("scenario 'text.yaml': line 3: physics_dt"), std::string::npos) << error;
  EXPECT_FALSE(ParseScenario("{unclosed", "text.yaml", &from_text, &error));
  EXPECT_NE(error.find("cannot read scenario 'text.yaml'"), std::string::npos) << error;
}

// issue 12: a typo or a wrong type inside a check no longer lets the default apply
TEST(ScenarioStrict, BadChecksAreRefusedWithLineAndKey) {
  ExpectRefused({
      {Variant(8, "  - {type: base_height, tolernce: 0.00001}"),
       "line 8: checks[0] (base_height): unknown key 'tolernce' (known: after, reference, "
       "tolerance, type, until)"},
      {Variant(8, "  - {type: not_fallen, min_hieght: 0.5}"),
       "line 8: checks[0] (not_fallen): unknown key 'min_hieght'"},
      {Variant(8, "  - {type: not_fallen, min_height: \"low\"}"),
       "line 8: checks[0] (not_fallen): min_height: must be a number, not 'low'"},
      {Variant(8, "  - type: not_fallen\n    min_height: .nan"),
       "line 9: checks[0] (not_fallen): min_height: must be finite"},
      {Variant(8, "  - {type: levitates}"), "line 8: checks[0]: unknown check type 'levitates' (known: base_height"},
      {Variant(8, "  - {min_height: 0.5}"), "line 8: checks[0]: 'type' is required"},
      {Variant(8, "  - {type: base_height, tolerance: 0.01, tolerance: 0.02}"),
       "line 8: checks[0] (base_height): 'tolerance' is given twice"},
      {Variant(8, "  - {type: base_height, tolerance: -1}"), "tolerance: must be > 0, not -1"},
      {Variant(8, "  - {type: base_height, after: 5}"),
       "line 8: checks[0] (base_height): after: must be a time within the run, [0, 2] s, not 5"},
      {Variant(8, "  - {type: base_height, after: 1.5, until: 1.0}"), "'after' must come before 'until'"},
      {Variant(8, "  - {type: feet_carry_weight, after: 1}"),
       "checks[0] (feet_carry_weight): 'sensors' is required"},
      {Variant(8, "  - {type: feet_carry_weight, sensors: rfsensor}"), "sensors: must be a list"},
      {Variant(8, "  - {type: feet_carry_weight, sensors: []}"), "sensors: must name at least one"},
      {Variant(8, "  - {type: base_displacement, axis: w, max: 1}"), "axis: must be x, y or z, not 'w'"},
      {Variant(8, "  - {type: base_displacement, axis: x}"), "give 'min', 'max' or both"},
      {Variant(8, "  - {type: cop_inside, require_loaded: maybe}"), "require_loaded: must be true or false"},
      {Variant(8, "  - {type: settles, at: 1.95}"), "must end within the run"},
      {Variant(8, "  - {type: foot_lifted, sensor: lfsensor, after: 1}"), "'until' is required"},
      {Variant(8, "  - {type: real_time_factor}"), "'min' is required"},
      {Variant(8, "  - not_fallen"), "line 8: checks[0]: each check must be a mapping"},
  });
}

// issue 12: every value of the run is checked before anything starts
TEST(ScenarioStrict, BadRunValuesAreRefusedWithLineAndKey) {
  ExpectRefused({
      {Variant(3, "physics_dt: -1"), "line 3: physics_dt: -1 is outside the plausible range [1e-05, 0.02] s"},
      {Variant(3, "physics_dt: 0"), "line 3: physics_dt: 0 is outside the plausible range"},
      // issue 28 item 6: absurd but finite
      {Variant(3, "physics_dt: 1e-300"), "line 3: physics_dt: 1e-300 is outside the plausible range [1e-05, 0.02] s"},
      {Variant(4, "control_period: 1e-300"), "line 4: control_period: 1e-300 is outside the plausible range"},
      {Variant(3, "physics_dt: .nan"), "line 3: physics_dt: must be finite"},
      {Variant(3, "physics_dt: fast"), "line 3: physics_dt: must be a number, not 'fast'"},
      {Variant(2, "duration: 1e308"), "line 2: duration: 1e308 is outside the plausible range [0.001, 1e+06] s"},
      {Variant(2, "duration: 1e-300"), "line 2: duration: 1e-300 is outside the plausible range [0.001, 1e+06] s"},
      {Variant(2, "duration: 0.002"), "line 2: duration: 0.002000 s is shorter than one control period"},
      {Variant(2, "duration: [1, 2]"), "line 2: duration: must be a number, not a list"},
      {Variant(4, "control_period: 0.0015"), "line 4: control_period: 0.001500 s must be a whole multiple of physics_dt"},
      {Variant(4, "control_period: 0.0005"), "must be a whole multiple of physics_dt"},
      {Variant(0, "integrator: verlet"), "line 9: integrator: must be euler, rk4 or implicit, not 'verlet'"},
      {Variant(0, "contact: squishy"), "line 9: contact: must be soft, native, rigid or auto, not 'squishy'"},
      {Variant(0, "on_controller_loss: panic"), "line 9: on_controller_loss: must be end, wait or continue"},
      {Variant(0, "keyframe: \"\""), "line 9: keyframe: must not be empty"},
      {Variant(0, "realtime: maybe"), "line 9: realtime: must be true or false"},
      {Variant(0, "expect_fall: maybe"), "line 9: expect_fall: must be true or false"},
      {Variant(0, "on_fall: panic"), "line 9: on_fall: must be end or continue"},
      {Variant(0, "fall_allow_contact: hand"), "line 9: fall_allow_contact: must be a list"},
      {Variant(0, "log_every: 0"), "line 9: log_every: 0 is outside the plausible range [1, 1e+09]"},
      {Variant(0, "log_every: 2.5"), "line 9: log_every: must be a whole number"},
      {Variant(0, "controller_timeout: 0"), "line 9: controller_timeout: 0 is outside the plausible range [0.001, 3600] s"},
      {Variant(0, "wall_timeout: -1"), "line 9: wall_timeout: must be in [0, 1e+06]"},
      {Variant(0, "name: a/b"), "line 9: name: 'a/b' must be letters, digits"},
      {Variant(0, "sim_args: --realtime"), "line 9: sim_args: must be a list"},
      {Variant(0, "plot_joints: [[a]]"), "line 9: plot_joints: must be a list of single values"},
      {Variant(0, "contact_params: {stifness: 1e6}"), "line 9: contact_params: unknown key 'stifness'"},
      {Variant(0, "contact_params: {exponent: 5}"), "line 9: contact_params: exponent: must be in [1, 3]"},
      {Variant(0, "contact_params: {damping: soft}"), "contact_params: damping: must be a number"},
      // issue 35: the joints' parameters (robot_model/joint_params.h)
      {Variant(0, "joint_params: {LARM_ELBOW: {stiffness: 1}}"),
       "line 9: joint_params: LARM_ELBOW: unknown key 'stiffness' (known: armature, damping, frictionloss)"},
      {Variant(0, "joint_params: {LARM_ELBOW: {damping: -1}}"),
       "line 9: joint_params: LARM_ELBOW: damping: must be in [0, 100000], not -1"},
      {Variant(0, "joint_params: {LARM_ELBOW: {armature: heavy}}"),
       "joint_params: LARM_ELBOW: armature: must be a number, not 'heavy'"},
      {Variant(0, "joint_params: {LARM_ELBOW: 2}"),
       "line 9: joint_params: LARM_ELBOW: must be a mapping of armature, damping and/or frictionloss"},
      {Variant(0, "joint_params: [LARM_ELBOW]"), "line 9: joint_params: must be a mapping of joints"},
      {Variant(0, "effects: {gravty: off}"), "line 9: effects: unknown effect 'gravty'"},
      {Variant(0, "effects: {noise.force: -1}"), "line 9: effects: noise.force must be a standard deviation >= 0"},
      {Variant(0, "duration: 3"), "line 9: 'duration' is given twice"},
      {Variant(0, "pushes: [{at: 1, at: 0.5, direction: 0, impulse: 1}]"),
       "line 9: pushes[0]: 'at' is given twice"},
      {Variant(0, "duraton: 3"), "line 9: unknown key 'duraton'"},
      {Variant(6, "  - {program: posture, arg: [--ramp, \"1.0\"]}"),
       "line 6: controllers[0]: unknown key 'arg' (known: args, program)"},
      {Variant(6, "  - {program: posture, args: --ramp}"), "line 6: controllers[0]: args: must be a list"},
      {Variant(6, "  - {program: [posture]}"), "line 6: controllers[0]: program: must be a single value"},
      {Variant(6, "  - posture"), "line 6: controllers[0]: must be a mapping"},
  });
}

// issue 10: `{out}` in a controller's args or in sim_args is the run's output folder; any
// other placeholder is refused with its line, the key and what would work
TEST(ScenarioStrict, UnknownPlaceholdersAreRefused) {
  ExpectRefused({
      {Variant(6, "  - {program: posture, args: [--log, \"{output}/walk.csv\"]}"),
       "line 6: controllers[0]: args[1]: unknown placeholder '{output}' in '{output}/walk.csv' "
       "(the only one is {out}, the run's output folder, e.g. \"{out}/walk.csv\")"},
      {Variant(6, "  - program: posture\n    args:\n      - --log\n      - \"{out}/{name}.csv\""),
       "line 9: controllers[0]: args[1]: unknown placeholder '{name}'"},
      {Variant(0, "sim_args: [--extra, \"{dir}/x\"]"), "line 9: sim_args[1]: unknown placeholder '{dir}'"},
  });
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(Temp(Variant(6, "  - {program: posture, args: [--log, \"{out}/walk.csv\"]}") +
                                "sim_args: [--extra, \"{out}/x\"]\n"),
                           &s, &error)) << error;
  EXPECT_EQ(s.controllers[0].args[1], "{out}/walk.csv");  // expanded when the run starts
}

// issue 10: the walk checks' keys
TEST(ScenarioStrict, BadWalkChecksAreRefused) {
  ExpectRefused({
      {Variant(8, "  - {type: average_speed}"), "line 8: checks[0] (average_speed): 'min' is required"},
      {Variant(8, "  - {type: average_speed, min: 0}"), "average_speed): min: must be > 0, not 0"},
      {Variant(8, "  - {type: average_speed, min: 0.2, threshold: -1}"), "threshold: must be > 0"},
      {Variant(8, "  - {type: goal_reached, yaw: 90}"),
       "checks[0] (goal_reached): unknown key 'yaw' (known: from, tolerance, tolerance_deg, type, x, y, yaw_deg)"},
      {Variant(8, "  - {type: goal_reached, x: far}"), "goal_reached): x: must be a number, not 'far'"},
      {Variant(8, "  - {type: goal_reached, x: 1, tolerance: 0}"), "tolerance: must be > 0, not 0"},
  });
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(Temp(Variant(8, "  - {type: goal_reached, x: 10, yaw_deg: 180}\n"
                                           "  - {type: average_speed, min: 0.25}")),
                           &s, &error)) << error;
  EXPECT_EQ(s.checks[0].Number("tolerance"), 0.2);
  EXPECT_EQ(s.checks[0].Number("tolerance_deg"), 5);
  EXPECT_EQ(s.checks[0].Number("y"), 0);
  EXPECT_EQ(s.checks[1].Number("threshold"), 0.02);
}

// issue 12: a scenario cut short is not a passing run; controllers: [] runs without one
TEST(ScenarioStrict, NoChecksOrNoControllersIsAnError) {
  // the first `n` lines of the valid scenario, without lines `skip`
  const auto first = [](size_t n, std::vector<size_t> skip = {}) {
    std::string out;
    for (size_t i = 0; i < n; ++i)
      if (std::find(skip.begin(), skip.end(), i + 1) == skip.end()) out += kValid[i] + "\n";
    return out;
  };
  ExpectRefused({
      {first(6), "'checks' is missing: a scenario must check something"},
      {first(7), "line 7: 'checks' must be a list"},
      {first(6) + "checks: []\n", "line 7: 'checks' is empty"},
      {first(8, {3, 4, 5, 6}), "'controllers' is missing: list them ({program, args}), or write 'controllers: []'"},
      {first(8, {6}), "line 5: 'controllers' must be a list"},
  });
  Scenario s;
  std::string error;
  const std::string none = kValid[0] + "\ncontrollers: []\n" + kValid[6] + "\n" + kValid[7] + "\n";
  ASSERT_TRUE(LoadScenario(Temp(none), &s, &error)) << error;
  EXPECT_TRUE(s.controllers.empty());
}

// issue 12: stand.yaml cut at any line boundary before its first check is refused
TEST(ScenarioStrict, AShippedScenarioCutShortIsRefused) {
  std::ifstream in(std::string(OHRP_SOURCE_DIR) + "/scenarios/stand.yaml");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  std::string prefix;
  size_t cut = 0;
  for (; cut < lines.size() && lines[cut].rfind("  - type:", 0) != 0; ++cut) {
    Scenario s;
    std::string error;
    EXPECT_FALSE(LoadScenario(Temp(prefix), &s, &error)) << "cut after line " << cut;
    prefix += lines[cut] + "\n";
  }
  EXPECT_GT(cut, 10u);  // the cut reached the checks
}

// every scenario of the repository loads (scenarios/ and the tests' own)
TEST(ScenarioStrict, EveryScenarioFileLoads) {
  int loaded = 0;
  for (const char* dir : {"scenarios", "tests/integration"}) {
    for (const auto& e : fs::directory_iterator(fs::path(OHRP_SOURCE_DIR) / dir)) {
      if (e.path().extension() != ".yaml") continue;
      Scenario s;
      std::string error;
      EXPECT_TRUE(LoadScenario(e.path().string(), &s, &error)) << error;
      EXPECT_FALSE(s.checks.empty()) << e.path();
      ++loaded;
    }
  }
  EXPECT_GE(loaded, 14);
}

// the docs' table of checks is the parser's table
TEST(ScenarioStrict, TheDocsListTheCheckKeysOfTheParser) {
  std::ifstream in(std::string(OHRP_SOURCE_DIR) + "/docs/scenarios.md");
  std::stringstream doc;
  doc << in.rdbuf();
  EXPECT_NE(doc.str().find(CheckTableMarkdown()), std::string::npos)
      << "docs/scenarios.md, section Checks, should hold this table:\n" << CheckTableMarkdown();
}

// the defaults the evaluators read are the table's, and the docs show them
TEST(ScenarioStrict, TheTableHoldsTheDefaultsTheEvaluatorsUse) {
  for (const auto& type : CheckTypes()) {
    for (const auto& key : type.keys) {
      if (std::isnan(key.fallback)) continue;
      char shown[32];
      std::snprintf(shown, sizeof(shown), "%g", key.fallback);
      const std::string doc = key.doc;
      EXPECT_EQ(doc.substr(doc.size() - std::min(doc.size(), std::strlen(shown))), shown)
          << type.type << "." << key.name << ": the docs say '" << doc << "'";
      CheckSpec spec;
      spec.type = type.type;
      EXPECT_EQ(spec.Number(key.name), key.fallback) << type.type << "." << key.name;
    }
  }
  // the push tool's specs (recovery.h) start from the same defaults
  const StandingSpec standing;
  EXPECT_EQ(CheckDefault("standing", "min_height_fraction"), standing.min_height_fraction);
  EXPECT_EQ(CheckDefault("standing", "max_tilt_deg"), standing.max_tilt_deg);
  EXPECT_EQ(CheckDefault("standing", "load_tolerance"), standing.load_tolerance);
  const SettleSpec settle;
  EXPECT_EQ(CheckDefault("settles", "duration"), settle.duration);
  EXPECT_EQ(CheckDefault("settles", "baseline"), settle.baseline);
  EXPECT_EQ(CheckDefault("settles", "tolerance"), settle.tolerance);
  EXPECT_EQ(CheckDefault("settles", "fraction"), settle.fraction);
  EXPECT_EQ(CheckDefault("settles", "within"), settle.within);
  EXPECT_TRUE(std::isnan(CheckDefault("standing", "stance_at")));
}

}  // namespace
}  // namespace ohrp::runner
