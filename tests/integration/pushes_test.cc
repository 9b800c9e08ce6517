// Tests the scenario key `pushes` (tools/runner/src/pushes.cc): the conversion to sim_host's
// --push values and the refusal of bad entries with file, line and key.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "runner/scenario.h"
#include "temp_file.h"

namespace ohrp::runner {
namespace {

// the numbers of a --push value
std::vector<double> Values(const std::string& arg) {
  std::vector<double> v;
  std::stringstream ss(arg);
  for (std::string x; std::getline(ss, x, ',');) v.push_back(std::stod(x));
  return v;
}

constexpr const char* kHead = "scene: a.xml\nduration: 5\n";
constexpr const char* kTail = "controllers: []\nchecks: [{type: not_fallen}]\n";

TEST(Pushes, DirectionAndImpulseBecomeAForceOverTheWindow) {
  Scenario s;
  std::string error;
  ASSERT_TRUE(LoadScenario(Temp(std::string(kHead) +
                                "pushes:\n"
                                "  - {at: 1.0, direction: 90, impulse: 15}\n"
                                "  - {at: 2.0, duration: 0.2, direction: 225, impulse: 30}\n"
                                "  - {at: 3.0, duration: 0.05, force: [1, -2, 3]}\n" + kTail),
                           &s, &error))
      << error;
  ASSERT_EQ(s.pushes.size(), 3u);
  // 15 N s over the default 0.1 s to the left (+y): 150 N along y
  auto v = Values(PushArgument(s.pushes[0]));
  ASSERT_EQ(v.size(), 8u);
  EXPECT_DOUBLE_EQ(v[0], 1.0);
  EXPECT_DOUBLE_EQ(v[1], 1.1);
  EXPECT_NEAR(v[2], 0.0, 1e-12);
  EXPECT_NEAR(v[3], 150.0, 1e-12);
  for (int k = 4; k < 8; ++k) EXPECT_EQ(v[k], 0.0);
  // 30 N s over 0.2 s back and right: 150 N at 225 deg, i.e. -106.07 N on x and on y
  v = Values(PushArgument(s.pushes[1]));
  EXPECT_DOUBLE_EQ(v[1], 2.2);
  EXPECT_NEAR(v[2], -150 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(v[3], -150 / std::sqrt(2.0), 1e-9);
  EXPECT_NEAR(std::hypot(v[2], v[3]) * (v[1] - v[0]), 30.0, 1e-9);  // the impulse
  // an explicit force goes through as written
  v = Values(PushArgument(s.pushes[2]));
  EXPECT_DOUBLE_EQ(v[2], 1);
  EXPECT_DOUBLE_EQ(v[3], -2);
  EXPECT_DOUBLE_EQ(v[4], 3);
}

// each bad entry: the message names the file, the line of the push and the key
TEST(Pushes, BadEntriesAreRefusedWithFileLineAndKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"  - {at: 1, direction: 0, impulse: 5, speed: 3}\n", "unknown key 'speed'"},
      {"  - {direction: 0, impulse: 5}\n", "'at' is required"},
      {"  - {at: 1, impulse: 5}\n", "'direction' is required"},
      {"  - {at: 1, direction: 0}\n", "'impulse' is required"},
      {"  - {at: soon, direction: 0, impulse: 5}\n", "'at' must be a number"},
      {"  - {at: 1, direction: 0, impulse: .nan}\n", "'impulse' must be finite"},
      {"  - {at: 1, direction: 0, impulse: -5}\n", "'impulse' must be >= 0"},
      {"  - {at: -1, direction: 0, impulse: 5}\n", "'at' must be >= 0"},
      {"  - {at: 1, duration: 0, direction: 0, impulse: 5}\n", "'duration' must be > 0"},
      {"  - {at: 1, force: [1, 2]}\n", "'force' must be a list of 3 numbers"},
      {"  - {at: 1, force: [1, 2, x]}\n", "'force' must be a list of 3 numbers"},
      {"  - {at: 1, force: [1, 2, 3], impulse: 4}\n", "either 'force' or 'direction'"},
      {"  - 7\n", "must be a mapping"},
  };
  for (const auto& [entry, message] : cases) {
    Scenario s;
    std::string error;
    // the bad push is the second, on line 5 of the file
    const std::string path =
        Temp(std::string(kHead) + "pushes:\n  - {at: 0.5, direction: 0, impulse: 1}\n" + entry);
    EXPECT_FALSE(LoadScenario(path, &s, &error)) << entry;
    EXPECT_NE(error.find(message), std::string::npos) << entry << ": " << error;
    EXPECT_NE(error.find("'" + path + "': line 5: pushes[1]"), std::string::npos) << error;
  }
}

TEST(Pushes, APushAfterTheRunOrNotAListIsRefused) {
  Scenario s;
  std::string error;
  EXPECT_FALSE(LoadScenario(Temp(std::string(kHead) + "pushes:\n  - {at: 4.95, direction: 0, impulse: 1}\n"),
                            &s, &error));
  EXPECT_NE(error.find("ends after the run"), std::string::npos) << error;
  EXPECT_FALSE(LoadScenario(Temp(std::string(kHead) + "pushes: {at: 1}\n"), &s, &error));
  EXPECT_NE(error.find("line 3: 'pushes' must be a list"), std::string::npos) << error;
}

TEST(Pushes, TheShippedPushScenariosParse) {
  for (const char* name : {"push_small", "push_large"}) {
    Scenario s;
    std::string error;
    ASSERT_TRUE(LoadScenario(std::string(OHRP_SOURCE_DIR) + "/scenarios/" + name + ".yaml", &s, &error)) << error;
    ASSERT_EQ(s.pushes.size(), 1u);
    EXPECT_EQ(s.keyframe, "halfsit");
  }
}

}  // namespace
}  // namespace ohrp::runner
