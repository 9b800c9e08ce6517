// Tests the push tool's bisection (tools/push/src/bisect.cc) on trials with a known threshold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "common/scratch.h"
#include "push/push.h"

namespace ohrp::push {
namespace {

// a robot that stands up to `threshold` N s; the number of trials is 1 + ceil(log2(max / tol))
TEST(Bisect, BracketsAKnownThresholdWithinTheTolerance) {
  for (double threshold : {0.7, 13.0, 37.3, 99.9, 150.0, 199.0}) {
    std::vector<double> tried;
    const Limit l = BisectLargest(200, 2, [&](double j) {
      tried.push_back(j);
      return j <= threshold ? Outcome::kStanding : Outcome::kFell;
    });
    EXPECT_FALSE(l.failed);
    EXPECT_FALSE(l.above_max);
    EXPECT_LE(l.largest, threshold) << threshold;
    EXPECT_GT(l.smallest_fall, threshold) << threshold;
    EXPECT_LE(l.smallest_fall - l.largest, 2.0);
    EXPECT_EQ(l.trials, 1 + static_cast<int>(std::ceil(std::log2(200.0 / 2))));  // 8
    EXPECT_EQ(static_cast<int>(tried.size()), l.trials);
    EXPECT_DOUBLE_EQ(tried.front(), 200);
  }
}

TEST(Bisect, StandingAtTheTopOrAFailedTrialEndsIt) {
  Limit l = BisectLargest(100, 5, [](double) { return Outcome::kStanding; });
  EXPECT_TRUE(l.above_max);
  EXPECT_EQ(l.largest, 100);
  EXPECT_EQ(l.trials, 1);
  int n = 0;
  l = BisectLargest(100, 5, [&](double) { return ++n == 3 ? Outcome::kFailed : Outcome::kFell; });
  EXPECT_TRUE(l.failed);
  EXPECT_EQ(l.trials, 3);
  // falling at every impulse: the answer is the bottom of the bracket, within the tolerance
  l = BisectLargest(100, 5, [](double) { return Outcome::kFell; });
  EXPECT_EQ(l.largest, 0);
  EXPECT_LE(l.smallest_fall, 5);
}

// the options a user can get wrong are refused with a message naming the option
TEST(Options, BadValuesAreNamed) {
  PushOptions o;
  o.source_dir = OHRP_SOURCE_DIR;
  o.bin_dir = "/nonexistent";
  std::string error;
  EXPECT_FALSE(ValidateOptions(o, &error));  // posture is not in /nonexistent
  EXPECT_NE(error.find("controller program"), std::string::npos) << error;
  o.controllers = {"/bin/true"};
  EXPECT_TRUE(ValidateOptions(o, &error)) << error;
  auto refused = [&](PushOptions bad, const std::string& word) {
    std::string e;
    EXPECT_FALSE(ValidateOptions(bad, &e)) << word;
    EXPECT_NE(e.find(word), std::string::npos) << e;
  };
  PushOptions b = o;
  b.tolerance = 0;
  refused(b, "--tolerance");
  b = o;
  b.max_impulse = NAN;
  refused(b, "--max-impulse");
  b = o;
  b.directions = {0, INFINITY};
  refused(b, "directions");
  b = o;
  b.push_duration = 0;
  refused(b, "--push-duration");
  b = o;
  b.settle_impulse = 15;
  b.settle_within = 10;
  refused(b, "--settle-within");
  b = o;
  b.scene = "no/such/scene.xml";
  refused(b, "scene");
  b = o;
  b.controllers = {"/bin/true --command 'velocity 0.2 0 0 6"};  // the quote not closed
  refused(b, "quote");
  b = o;
  b.controllers = {"/bin/true --command 'velocity 0.2 0 0 6'"};  // one quoted argument
  EXPECT_TRUE(ValidateOptions(b, &error)) << error;
  b = o;
  b.controllers = {"  "};
  refused(b, "empty");
}

}  // namespace
}  // namespace ohrp::push

// the standing judgement reads the soles' F/T sensors of the scene's robot, not HRP-1S's names
namespace ohrp::push {
namespace {

std::vector<std::string> Sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

TEST(FootSensors, AreTheSolesSensorsOfTheScenesRobot) {
  std::vector<std::string> names;
  std::string error;
  ASSERT_TRUE(FootSensorsOf(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", &names, &error))
      << error;
  EXPECT_EQ(Sorted(names), (std::vector<std::string>{"lfsensor", "rfsensor"}));  // not the hands'
  const std::string g1 = std::string(OHRP_SOURCE_DIR) + "/robots/g1.yaml";
  if (std::filesystem::exists(std::string(OHRP_SOURCE_DIR) + "/../shared/external/menagerie/unitree_g1")) {
    ASSERT_TRUE(FootSensorsOf(g1, &names, &error)) << error;
    EXPECT_EQ(Sorted(names), (std::vector<std::string>{"left_foot_ft", "right_foot_ft"}));
  }
}

TEST(FootSensors, ARobotWithoutSoleSensorsIsRefusedNamingTheOption) {
  const std::string scene = ohrp::testing::ScratchFile(
      "nosoles",
      "<mujoco><worldbody><body name=\"b\"><freejoint/><geom size=\"0.1\"/>"
      "<body name=\"l\"><joint name=\"j\"/><geom size=\"0.05\"/></body></body></worldbody>"
      "<actuator><motor joint=\"j\"/></actuator></mujoco>",
      ".xml");
  std::vector<std::string> names;
  std::string error;
  EXPECT_FALSE(FootSensorsOf(scene, &names, &error));
  EXPECT_NE(error.find("--foot-sensors"), std::string::npos) << error;
}

}  // namespace
}  // namespace ohrp::push
