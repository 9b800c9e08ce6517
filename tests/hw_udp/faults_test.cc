// Tests hw_emulator's fault plan: command-line events, control-file lines, following the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/scratch.h"
#include "faults.h"

namespace ohrp::hw::udp {
namespace {

constexpr int kBoards = 6, kForces = 4, kImus = 1;

// a joint's board reading a given value (NaN and 1e300 included) for a while
TEST(FaultPlan, AJointValueActsForItsDurationAndAnyNumberIsTaken) {
  std::vector<FaultEvent> ev;
  std::string e;
  ASSERT_TRUE(ParseEvent("--value", "3=1e300@2.0+0.2", kBoards, kForces, kImus, &ev, &e)) << e;
  FaultState s;
  ApplyDue(1.9, &ev, &s);
  EXPECT_EQ(s.value_joint, -1);
  ApplyDue(2.0, &ev, &s);
  EXPECT_EQ(s.value_joint, 3);
  EXPECT_EQ(s.value, 1e300);
  ApplyDue(2.2, &ev, &s);
  EXPECT_EQ(s.value_joint, -1);
  for (const char* bad : {"3@2.0", "x=1@2", "3=@2", "3=1e300", "-1=0@1"}) {
    EXPECT_FALSE(ParseEvent("--value", bad, kBoards, kForces, kImus, &ev, &e)) << bad;
    EXPECT_NE(e.find("JOINT=VALUE@TIME"), std::string::npos) << e;
  }
  ASSERT_TRUE(ApplyControlLine("value 5 nan", kBoards, kForces, kImus, &s, &e)) << e;
  EXPECT_EQ(s.value_joint, 5);
  EXPECT_TRUE(std::isnan(s.value));
  ASSERT_TRUE(ApplyControlLine("value off", kBoards, kForces, kImus, &s, &e)) << e;
  EXPECT_EQ(s.value_joint, -1);
  EXPECT_FALSE(ApplyControlLine("value 5", kBoards, kForces, kImus, &s, &e));
}

TEST(FaultPlan, EventsActAtTheirTime) {
  std::vector<FaultEvent> ev;
  std::string e;
  ASSERT_TRUE(ParseEvent("--silent", "2@0.5+0.25", kBoards, kForces, kImus, &ev, &e)) << e;
  ASSERT_TRUE(ParseEvent("--reset", "1@0.3", kBoards, kForces, kImus, &ev, &e)) << e;
  ASSERT_TRUE(ParseEvent("--stuck", "ft1@0.1", kBoards, kForces, kImus, &ev, &e)) << e;
  ASSERT_TRUE(ParseEvent("--saturate", "imu0@0.2", kBoards, kForces, kImus, &ev, &e)) << e;
  ASSERT_TRUE(ParseEvent("--estop", "0.4", kBoards, kForces, kImus, &ev, &e)) << e;
  FaultState s;
  ApplyDue(0.05, &ev, &s);
  EXPECT_EQ(s.stuck, 0u);
  ApplyDue(0.3, &ev, &s);
  EXPECT_EQ(s.stuck, 1u << 1);
  EXPECT_EQ(s.saturated, 1u << 8);
  EXPECT_EQ(s.reset_request, 1u << 1);
  EXPECT_FALSE(s.estop);
  ApplyDue(0.5, &ev, &s);
  EXPECT_TRUE(s.estop);
  EXPECT_EQ(s.silent, 1u << 2);
  s.reset_request = 0;
  ApplyDue(0.8, &ev, &s);
  EXPECT_EQ(s.silent, 0u);
  EXPECT_EQ(s.reset_request, 0u);  // each event acts once
}

TEST(FaultPlan, MalformedEventsSayWhatIsExpected) {
  std::vector<FaultEvent> ev;
  std::string e;
  EXPECT_FALSE(ParseEvent("--silent", "6@1", kBoards, kForces, kImus, &ev, &e));
  EXPECT_NE(e.find("BOARD 0..5"), std::string::npos) << e;
  EXPECT_FALSE(ParseEvent("--stuck", "ft4@1", kBoards, kForces, kImus, &ev, &e));
  EXPECT_NE(e.find("ft0..ft3"), std::string::npos) << e;
  EXPECT_FALSE(ParseEvent("--reset", "1@1+2", kBoards, kForces, kImus, &ev, &e));
  EXPECT_FALSE(ParseEvent("--estop", "x", kBoards, kForces, kImus, &ev, &e));
  EXPECT_FALSE(ParseEvent("--silent", "1", kBoards, kForces, kImus, &ev, &e));
  EXPECT_TRUE(ev.empty());
}

TEST(FaultPlan, ControlLinesChangeTheFaults) {
  FaultState s;
  std::string e;
  EXPECT_TRUE(ApplyControlLine("loss 0.05", kBoards, kForces, kImus, &s, &e)) << e;
  EXPECT_DOUBLE_EQ(s.loss, 0.05);
  EXPECT_TRUE(ApplyControlLine("late 0.5 3", kBoards, kForces, kImus, &s, &e)) << e;
  EXPECT_DOUBLE_EQ(s.late_s, 0.003);
  EXPECT_TRUE(ApplyControlLine("silent 4", kBoards, kForces, kImus, &s, &e));
  EXPECT_TRUE(ApplyControlLine("stuck imu0", kBoards, kForces, kImus, &s, &e));
  EXPECT_TRUE(ApplyControlLine("estop on", kBoards, kForces, kImus, &s, &e));
  EXPECT_TRUE(ApplyControlLine("reset 0", kBoards, kForces, kImus, &s, &e));
  EXPECT_TRUE(ApplyControlLine("# a comment", kBoards, kForces, kImus, &s, &e));
  EXPECT_EQ(s.silent, 1u << 4);
  EXPECT_EQ(s.stuck, 1u << 8);
  EXPECT_TRUE(s.estop);
  EXPECT_TRUE(ApplyControlLine("talk 4", kBoards, kForces, kImus, &s, &e));
  EXPECT_EQ(s.silent, 0u);
  EXPECT_TRUE(ApplyControlLine("clear", kBoards, kForces, kImus, &s, &e));
  EXPECT_EQ(s.loss, 0.0);
  EXPECT_FALSE(s.estop);
  EXPECT_EQ(s.reset_request, 1u);  // a requested reset still happens
  EXPECT_FALSE(ApplyControlLine("loss 2", kBoards, kForces, kImus, &s, &e));
  EXPECT_FALSE(ApplyControlLine("explode 1", kBoards, kForces, kImus, &s, &e));
  EXPECT_NE(e.find("not understood"), std::string::npos);
}

TEST(ControlFile, ReturnsOnlyCompleteNewLines) {
  const std::string path = ohrp::testing::ScratchPath("control");
  ControlFile f(path);
  EXPECT_TRUE(f.NewLines().empty());  // not there yet
  {
    std::ofstream out(path);
    out << "loss 0.1\nsilent";
  }
  EXPECT_EQ(f.NewLines(), std::vector<std::string>{"loss 0.1"});
  {
    std::ofstream out(path, std::ios::app);
    out << " 2\nclear\n";
  }
  EXPECT_EQ(f.NewLines(), (std::vector<std::string>{"silent 2", "clear"}));
  EXPECT_TRUE(f.NewLines().empty());
  std::remove(path.c_str());
}

}  // namespace
}  // namespace ohrp::hw::udp
