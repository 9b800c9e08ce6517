// Tests `sim_host --explain` on robots nobody here modelled, loaded as their authors wrote them
// (../shared/external: menagerie's Unitree H1 and Agility Cassie, MuJoCo 2.2.2's humanoid and
// humanoid100): the control period chosen from each scene's step, each actuator's type and the
// mapping of the servo's torque onto it, and the passive joints published read-only. Skipped
// when the external models are not beside the repository.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include <chrono>
#include <thread>

#include "../controllers/fake_robot.h"  // ExternalDir, Program, Spawn, WaitExit, TempPath, ReadFile
#include "shm_bridge/bridge.h"

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
  bool Says(const std::string& text) { return ct::ReadFile(log_).find(text) != std::string::npos; }
  std::string external_, log_;
};

TEST_F(RobotsExplained, UnitreeH1RunsAtTheMultipleOfItsStepNearest5ms) {
  ASSERT_EQ(Explain("menagerie/unitree_h1/scene.xml"), 0) << ct::ReadFile(log_);
  EXPECT_TRUE(Says("physics step 0.002 s, control period 0.004 s (2 steps per cycle")) << ct::ReadFile(log_);
  EXPECT_TRUE(Says("left_knee: motor gear=1: ctrl = tau/1, ctrl in [-300, 300]; torque limit 300"))
      << ct::ReadFile(log_);
  EXPECT_TRUE(Says("passive joints (0, read-only): none")) << ct::ReadFile(log_);
  // an explicit period that does not divide the step names the ones that would
  EXPECT_EQ(Explain("menagerie/unitree_h1/scene.xml", {"--control-period", "0.005"}), 2);
  EXPECT_TRUE(Says("use --control-period 0.004 or 0.006")) << ct::ReadFile(log_);
}

TEST_F(RobotsExplained, CassiesGearedMotorsAndPassiveJoints) {
  ASSERT_EQ(Explain("menagerie/agility_cassie/scene.xml"), 0) << ct::ReadFile(log_);
  EXPECT_TRUE(Says("control period 0.005 s (10 steps per cycle")) << ct::ReadFile(log_);
  EXPECT_TRUE(Says("left-knee: motor gear=16: ctrl = tau/16, ctrl in [-12.2, 12.2]; torque limit 195.2"))
      << ct::ReadFile(log_);
  EXPECT_TRUE(Says("left-foot: motor gear=50: ctrl = tau/50")) << ct::ReadFile(log_);
  EXPECT_TRUE(Says("passive joints (10, read-only): left-shin left-tarsus")) << ct::ReadFile(log_);
}

TEST_F(RobotsExplained, MujocosHumanoidsWithTheirGears) {
  for (const char* scene : {"mujoco-2.2.2-models/humanoid/humanoid.xml",
                            "mujoco-2.2.2-models/humanoid100/humanoid100.xml"}) {
    ASSERT_EQ(Explain(scene), 0) << scene << "\n" << ct::ReadFile(log_);
    EXPECT_TRUE(Says("actuation (21 commanded joints")) << ct::ReadFile(log_);
    EXPECT_TRUE(Says("right_hip_y: motor gear=120: ctrl = tau/120, ctrl in [-1, 1]; torque limit 120"))
        << ct::ReadFile(log_);
    // humanoid100's hundred free objects are not the robot's joints
    EXPECT_TRUE(Says("passive joints (0, read-only): none")) << ct::ReadFile(log_);
  }
}

//---------------- passive joints in the segment ----------------

TEST_F(RobotsExplained, ACassieControllerSeesItsShinAndTarsus) {
  const std::string segment = ct::UniqueSegment("cassie_passive");
  ct::RemoveSegment(segment);
  const pid_t sim = ct::Spawn({ct::Program("sim_host"), "--scene",
                               external_ + "/menagerie/agility_cassie/scene.xml", "--keyframe",
                               "home", "--segment", segment, "--duration", "0.05",
                               "--on-controller-loss", "continue", "--quiet"},
                              log_);
  shm::RobotAdaptor a;
  shm::Status st;
  for (int i = 0; i < 1000 && !(st = a.open(segment)).ok(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(st.ok()) << st.message << "\n" << ct::ReadFile(log_);
  const shm::SegmentHeader& h = a.header();
  EXPECT_EQ(h.njoint, 10);
  ASSERT_EQ(h.npassive, 10);
  EXPECT_STREQ(h.passive_names[0], "left-shin");
  EXPECT_STREQ(h.passive_names[1], "left-tarsus");
  shm::SensorBlock s{};
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  // the home keyframe's tarsus angle, one control period later (the joint is held by its
  // linkage, not commanded)
  EXPECT_NEAR(s.passive_q[1], 1.42671, 0.05);
  for (int i = 0; i < h.npassive; ++i) {
    EXPECT_TRUE(std::isfinite(s.passive_q[i]) && std::isfinite(s.passive_dq[i])) << i;
  }
  // answer one cycle (hold), so that the run goes on without us once we leave
  shm::CommandBlock c{};
  c.njoint = h.njoint;
  for (int j = 0; j < h.njoint; ++j) {
    c.joint[j] = {shm::JointMode::kPosition, 0, s.q[j], 0.0, 0.0, h.default_kp[j], h.default_kd[j]};
  }
  ASSERT_EQ(a.write(c), shm::ReadResult::kOk);
  ASSERT_EQ(a.read(&s), shm::ReadResult::kOk);
  a.close();
  EXPECT_EQ(ct::WaitExit(sim, 30.0), 0) << ct::ReadFile(log_);
}

}  // namespace
}  // namespace ohrp::sim
