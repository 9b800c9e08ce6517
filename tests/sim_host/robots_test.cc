// Tests `sim_host --explain` on robots nobody here modelled, loaded as their authors wrote them
// (../shared/external: menagerie's Unitree H1 and Agility Cassie, MuJoCo 2.2.2's humanoid and
// humanoid100): the control period chosen from each scene's step, each actuator's type and the
// mapping of the servo's torque onto it, and the passive joints published read-only. Skipped
// when the external models are not beside the repository.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "../controllers/fake_robot.h"  // ExternalDir, Program, Spawn, WaitExit, TempPath, ReadText

namespace ohrp::sim {
namespace {

namespace ct = controllers::testing;

class RobotsExplained : public ::testing::Test {
 protected:
  void SetUp() override {
    external_ = ct::ExternalDir();
    if (external_.empty()) GTEST_SKIP() << "no ../shared/external beside the repository";
    log_ = ct::TempPath("robots_explain");
  }
  void TearDown() override {
    if (!log_.empty()) std::remove(log_.c_str());
  }
  // runs `sim_host --scene <external>/scene --explain [extra]`; returns its exit code
  int Explain(const std::string& scene, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args = {ct::Program("sim_host"), "--scene", external_ + "/" + scene,
                                     "--explain"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::remove(log_.c_str());
    return ct::WaitExit(ct::Spawn(args, log_), 60.0);
  }
  bool Says(const std::string& text) { return ct::ReadText(log_).find(text) != std::string::npos; }
  std::string external_, log_;
};

TEST_F(RobotsExplained, UnitreeH1RunsAtTheMultipleOfItsStepNearest5ms) {
  ASSERT_EQ(Explain("menagerie/unitree_h1/scene.xml"), 0) << ct::ReadText(log_);
  EXPECT_TRUE(Says("physics step 0.002 s, control period 0.004 s (2 steps per cycle")) << ct::ReadText(log_);
  EXPECT_TRUE(Says("left_knee: motor gear=1: ctrl = tau/1, ctrl in [-300, 300]; torque limit 300"))
      << ct::ReadText(log_);
  EXPECT_TRUE(Says("passive joints (0, read-only): none")) << ct::ReadText(log_);
  // an explicit period that does not divide the step names the ones that would
  EXPECT_EQ(Explain("menagerie/unitree_h1/scene.xml", {"--control-period", "0.005"}), 2);
  EXPECT_TRUE(Says("use --control-period 0.004 or 0.006")) << ct::ReadText(log_);
}

TEST_F(RobotsExplained, CassiesGearedMotorsAndPassiveJoints) {
  ASSERT_EQ(Explain("menagerie/agility_cassie/scene.xml"), 0) << ct::ReadText(log_);
  EXPECT_TRUE(Says("control period 0.005 s (10 steps per cycle")) << ct::ReadText(log_);
  EXPECT_TRUE(Says("left-knee: motor gear=16: ctrl = tau/16, ctrl in [-12.2, 12.2]; torque limit 195.2"))
      << ct::ReadText(log_);
  EXPECT_TRUE(Says("left-foot: motor gear=50: ctrl = tau/50")) << ct::ReadText(log_);
  EXPECT_TRUE(Says("passive joints (10, read-only): left-shin left-tarsus")) << ct::ReadText(log_);
}

TEST_F(RobotsExplained, MujocosHumanoidsWithTheirGears) {
  for (const char* scene : {"mujoco-2.2.2-models/humanoid/humanoid.xml",
                            "mujoco-2.2.2-models/humanoid100/humanoid100.xml"}) {
    ASSERT_EQ(Explain(scene), 0) << scene << "\n" << ct::ReadText(log_);
    EXPECT_TRUE(Says("actuation (21 commanded joints")) << ct::ReadText(log_);
    EXPECT_TRUE(Says("right_hip_y: motor gear=120: ctrl = tau/120, ctrl in [-1, 1]; torque limit 120"))
        << ct::ReadText(log_);
    // humanoid100's hundred free objects are not the robot's joints
    EXPECT_TRUE(Says("passive joints (0, read-only): none")) << ct::ReadText(log_);
  }
}

}  // namespace
}  // namespace ohrp::sim
