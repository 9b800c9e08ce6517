// Tests the one table of the sim_host options a scenario can set (cli/host_options.h): the
// table is well formed; sim_host registers each entry from it (name and help); the runner refuses
// a bad value naming the file, the line, the key and the range; and every committed scenario's
// sim_host arguments, parsed by sim_host's own command line, give sim_host the scenario's values.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "../../sim_host/src/command_line.h"
#include "cli/host_options.h"
#include "runner/commands.h"
#include "runner/scenario.h"

namespace ohrp {
namespace {

using cli::HostOption;
using cli::OptionType;

TEST(HostOptionTable, EveryEntryIsWellFormed) {
  std::set<std::string> keys, options;
  for (const HostOption& o : cli::kHostOptions) {
    SCOPED_TRACE(o.key);
    EXPECT_TRUE(keys.insert(o.key).second) << "repeated key";
    EXPECT_TRUE(options.insert(o.option).second) << "repeated option";
    EXPECT_EQ(std::string(o.option).rfind("--", 0), 0u);
    EXPECT_GT(std::string(o.help).size(), 10u);
    if (o.type == OptionType::kNumber) {
      if (o.range[0]) {
        EXPECT_NE(cli::FindPlausible(o.range), nullptr) << o.range;
      } else {
        EXPECT_LT(o.lo, o.hi);
      }
    }
    if (o.type == OptionType::kChoice) {
      EXPECT_GE(cli::HostOptionChoices(o).size(), 2u);
    }
    EXPECT_EQ(cli::FindHostOption(o.key), &o);
  }
  EXPECT_EQ(cli::FindHostOption("no_such_key"), nullptr);
  EXPECT_EQ(cli::HostOptionChoices(*cli::FindHostOption("integrator")),
            (std::vector<std::string>{"euler", "rk4", "implicit"}));
}

TEST(HostOptionTable, SimHostRegistersEveryEntryFromIt) {
  CLI::App app;
  sim::HostOptions o;
  sim::RawHostOptions r;
  sim::AddHostOptions(&app, &o, &r);
  for (const HostOption& e : cli::kHostOptions) {
    SCOPED_TRACE(e.key);
    const CLI::Option* opt = app.get_option_no_throw(e.option);
    ASSERT_NE(opt, nullptr);
    EXPECT_EQ(opt->get_description(), e.help);
  }
}

// a scenario with `extra` as its last keys, read from text
bool Read(const std::string& extra, runner::Scenario* s, std::string* error) {
  const std::string text = "scene: mjcf/hrp1s/scene_flat.xml\ncontrollers: []\n"
                           "checks: [{type: not_fallen}]\n" + extra;
  return runner::ParseScenario(text, "t.yaml", s, error);
}

TEST(HostOptionTable, TheRunnerRefusesABadValueNamingKeyLineAndRange) {
  runner::Scenario s;
  std::string error;
  for (const HostOption& o : cli::kHostOptions) {
    SCOPED_TRACE(o.key);
    std::string want;  // what the message must hold beyond the key and the line
    if (o.type == OptionType::kNumber)
      want = o.range[0] ? std::string("plausible range [") : "[" + cli::detail::Short(o.lo) + ", ";
    else if (o.type == OptionType::kChoice)
      want = cli::HostOptionChoices(o).back();
    else
      continue;
    EXPECT_FALSE(Read(std::string(o.key) + ": 2000000000\n", &s, &error));  // past every range
    EXPECT_NE(error.find("scenario 't.yaml': line 4: " + std::string(o.key) + ": "),
              std::string::npos) << error;
    EXPECT_NE(error.find(want), std::string::npos) << error;
  }
  // a number's type: log_every is a whole number of cycles
  EXPECT_FALSE(Read("log_every: 2.5\n", &s, &error));
  EXPECT_NE(error.find("line 4: log_every"), std::string::npos) << error;
  // a flag
  EXPECT_FALSE(Read("realtime: maybe\n", &s, &error));
  EXPECT_NE(error.find("line 4: realtime"), std::string::npos) << error;
}

TEST(HostOptionTable, TheRunnerLeavesOutUnsetValuesAndSimHostsDefaults) {
  runner::Scenario s;
  std::string error;
  ASSERT_TRUE(Read("on_fall: end\nrealtime: false\n", &s, &error)) << error;
  auto argv = runner::SimHostCommand(s, "sim_host", s.scene, "seg", "/out");
  for (const char* absent : {"--on-fall", "--realtime", "--physics-dt", "--control-period",
                             "--camera-rate", "--keyframe", "--integrator", "--contact", "--push",
                             "--effects", "--fall-allow-contact"})
    EXPECT_EQ(std::count(argv.begin(), argv.end(), absent), 0) << absent;
  // always passed: the run's length, the controller's loss and timeout, the log's rate
  for (const char* present : {"--duration", "--on-controller-loss", "--controller-timeout", "--log-every"})
    EXPECT_EQ(std::count(argv.begin(), argv.end(), present), 1) << present;
  ASSERT_TRUE(Read("on_fall: continue\nrealtime: true\nfall_allow_contact: [A, B]\n", &s, &error)) << error;
  argv = runner::SimHostCommand(s, "sim_host", s.scene, "seg", "/out");
  const auto at = std::find(argv.begin(), argv.end(), "--fall-allow-contact");
  ASSERT_NE(at, argv.end());
  EXPECT_EQ(*(at + 1), "A,B");
  EXPECT_EQ(*(std::find(argv.begin(), argv.end(), "--on-fall") + 1), "continue");
  EXPECT_EQ(std::count(argv.begin(), argv.end(), "--realtime"), 1);
}

// true when the scenario's own sim_args give `option` (they come last and win)
bool InSimArgs(const runner::Scenario& s, const std::string& option) {
  return std::find(s.sim_args.begin(), s.sim_args.end(), option) != s.sim_args.end();
}

// every committed scenario: its sim_host arguments, parsed by sim_host's own command line, give
// sim_host the values the scenario says (or sim_host's defaults where it says none)
TEST(HostOptionTable, CommittedScenariosReachSimHostAsWritten) {
  ASSERT_EQ(chdir(OHRP_SOURCE_DIR), 0);
  const std::filesystem::path out = std::filesystem::temp_directory_path() / "host_options_test";
  std::filesystem::create_directories(out);
  std::ofstream(out / "joint_params.yaml") << "joints: {}\n";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator("scenarios")) {
    if (entry.path().extension() != ".yaml") continue;
    SCOPED_TRACE(entry.path().string());
    runner::Scenario s;
    std::string error;
    ASSERT_TRUE(runner::LoadScenario(entry.path().string(), &s, &error)) << error;
    std::vector<std::string> argv = runner::SimHostCommand(s, "sim_host", s.scene, "seg", out.string());
    std::vector<char*> c_argv;
    for (auto& a : argv) c_argv.push_back(a.data());
    CLI::App app;
    sim::HostOptions o;
    sim::RawHostOptions r;
    sim::AddHostOptions(&app, &o, &r);
    ASSERT_NO_THROW(app.parse(static_cast<int>(c_argv.size()), c_argv.data()));
    ++count;
    EXPECT_EQ(o.duration, s.duration);
    EXPECT_EQ(o.controller_timeout, s.controller_timeout);
    EXPECT_EQ(o.log_every, s.log_every);
    EXPECT_EQ(r.loss, s.on_controller_loss);
    if (!InSimArgs(s, "--physics-dt")) {
      EXPECT_EQ(o.physics_dt, s.physics_dt);
    }
    if (!InSimArgs(s, "--control-period")) {
      EXPECT_EQ(o.control_period, s.control_period);
    }
    if (!InSimArgs(s, "--integrator")) {
      EXPECT_EQ(o.integrator, s.integrator);
    }
    if (!InSimArgs(s, "--keyframe")) {
      EXPECT_EQ(o.keyframe, s.keyframe);
    }
    if (!InSimArgs(s, "--realtime")) {
      EXPECT_EQ(o.realtime, s.realtime);
    }
    if (!InSimArgs(s, "--camera-rate")) {
      EXPECT_EQ(o.cameras.rate, s.camera_rate > 0 ? s.camera_rate : sim::HostOptions().cameras.rate);
    }
    if (!InSimArgs(s, "--contact")) {
      EXPECT_EQ(r.contact, s.contact.empty() ? "auto" : s.contact);
    }
    if (!InSimArgs(s, "--on-fall")) {
      EXPECT_EQ(r.on_fall, s.on_fall);
    }
    if (!InSimArgs(s, "--fall-allow-contact")) {
      EXPECT_EQ(o.fall.allow_contact, s.fall_allow_contact);
    }
    const size_t sim_arg_pushes = std::count(s.sim_args.begin(), s.sim_args.end(), "--push");
    EXPECT_EQ(r.pushes.size(), s.pushes.size() + sim_arg_pushes);
    for (size_t i = 0; i < s.pushes.size(); ++i) EXPECT_EQ(r.pushes[i], runner::PushArgument(s.pushes[i]));
    // the effects: the scenario's in the file's order, after a self_collisions check's request
    const YAML::Node effects = YAML::LoadFile(entry.path().string())["effects"];
    if (effects && effects.size() > 0) {
      ASSERT_FALSE(r.effects.empty());
      const auto it = std::find(r.effects.begin(), r.effects.end(), s.host_options.at("effects"));
      EXPECT_NE(it, r.effects.end());
      for (const auto& kv : effects) {
        const std::string key = kv.first.as<std::string>(), value = kv.second.as<std::string>();
        EXPECT_NE(it->find(key + "=" + value), std::string::npos) << key;
      }
    }
  }
  EXPECT_GT(count, 50);
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace ohrp
