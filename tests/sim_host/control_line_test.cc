// sim_host's control-channel parser (sim_host/control_channel.h): each verb and its numbers, and
// bad lines refused with an error that says what would work.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/scratch.h"
#include "sim_host/control_channel.h"

namespace ohrp::sim {
namespace {

class ControlLine : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ohrp::testing::ScratchFolder("control_line");
    std::filesystem::create_directories(dir_);
    const std::string path = (dir_ / "two.xml").string();
    std::ofstream(path) << R"(<mujoco><worldbody><body name="base"><freejoint/>
      <geom type="box" size="0.1 0.1 0.1"/><body name="arm" pos="0 0 0.2">
      <geom type="sphere" size="0.05"/></body></body></worldbody>
      <keyframe><key name="high" qpos="0 0 1 1 0 0 0"/></keyframe></mujoco>)";
    char error[512] = "";
    m_ = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    ASSERT_NE(m_, nullptr) << error;
  }
  void TearDown() override {
    if (m_) mj_deleteModel(m_);
    std::filesystem::remove_all(dir_);
  }
  // the error of a refused line ("" when it was accepted)
  std::string Refused(const std::string& line) {
    ControlAction a;
    std::string error;
    return ParseControlLine(line, m_, &a, &error) ? "" : error;
  }
  std::filesystem::path dir_;
  mjModel* m_ = nullptr;
};

TEST_F(ControlLine, Verbs) {
  ControlAction a;
  std::string error;
  ASSERT_TRUE(ParseControlLine("pause", m_, &a, &error)) << error;
  EXPECT_EQ(a.kind, ControlAction::kPause);
  ASSERT_TRUE(ParseControlLine("resume", m_, &a, &error)) << error;
  EXPECT_EQ(a.kind, ControlAction::kResume);
  ASSERT_TRUE(ParseControlLine("step", m_, &a, &error)) << error;
  EXPECT_EQ(a.kind, ControlAction::kStep);
  EXPECT_EQ(a.steps, 1);
  ASSERT_TRUE(ParseControlLine("step 25", m_, &a, &error)) << error;
  EXPECT_EQ(a.steps, 25);
  ASSERT_TRUE(ParseControlLine("reset", m_, &a, &error)) << error;
  EXPECT_EQ(a.kind, ControlAction::kReset);
  EXPECT_EQ(a.keyframe, -1);
  ASSERT_TRUE(ParseControlLine("reset high", m_, &a, &error)) << error;
  EXPECT_EQ(a.keyframe, 0);
  ASSERT_TRUE(ParseControlLine("push arm 10 -20 5.5 0.25", m_, &a, &error)) << error;
  EXPECT_EQ(a.kind, ControlAction::kPush);
  EXPECT_EQ(a.body, mj_name2id(m_, mjOBJ_BODY, "arm"));
  EXPECT_EQ(a.force[0], 10);
  EXPECT_EQ(a.force[1], -20);
  EXPECT_EQ(a.force[2], 5.5);
  EXPECT_EQ(a.duration, 0.25);
}

TEST_F(ControlLine, BadLinesSayWhatWouldWork) {
  EXPECT_NE(Refused("jump").find("unknown command 'jump' (commands: pause | resume | step [N]"),
            std::string::npos) << Refused("jump");
  EXPECT_NE(Refused("step 0").find("whole number of control periods"), std::string::npos);
  EXPECT_NE(Refused("step 1.5").find("whole number"), std::string::npos);
  EXPECT_NE(Refused("step x").find("whole number"), std::string::npos);
  EXPECT_NE(Refused("reset low").find("no keyframe 'low' in the model (its keyframes: high"),
            std::string::npos) << Refused("reset low");
  EXPECT_NE(Refused("push leg 1 0 0 0.1").find("no body 'leg' to push (the model's bodies: base, arm)"),
            std::string::npos) << Refused("push leg 1 0 0 0.1");
  EXPECT_NE(Refused("push world 1 0 0 0.1").find("no body 'world'"), std::string::npos);
  EXPECT_NE(Refused("push arm 1 zero 0 0.1").find("force y is not a finite number"), std::string::npos);
  EXPECT_NE(Refused("push arm 1 0 nan 0.1").find("force z is not a finite number"), std::string::npos);
  EXPECT_NE(Refused("push arm 1 0 0").find("the duration is seconds"), std::string::npos);
  EXPECT_NE(Refused("push arm 1 0 0 -1").find("the duration is seconds"), std::string::npos);
  EXPECT_NE(Refused("push arm 1e6 0 0 0.1").find("above 1e5 N"), std::string::npos);
  EXPECT_NE(Refused("pause now").find("unexpected 'now' after the command"), std::string::npos);
  EXPECT_EQ(Refused("pause").size(), 0u);
}

}  // namespace
}  // namespace ohrp::sim
