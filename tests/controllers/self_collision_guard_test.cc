// The online self-collision check (controllers/self_collision_guard.h) with HRP-1S's shipped
// file: a command that brings the right arm into the leg is held at the last safe references,
// one moving away is let through, the held cycles are reported with the pair, a file for
// another robot is refused, and a cycle allocates nothing.
#include "controllers/self_collision_guard.h"

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>

#include "../robot_model/count_allocations.h"

namespace ohrp::controllers {
namespace {

const std::string kFile = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
constexpr int kRarmShoulderR = 7, kRarmElbow = 9;

// the header of HRP-1S as the file describes it
shm::SegmentHeader Header(const collision::SelfCollisionFile& f) {
  shm::SegmentHeader h{};
  h.njoint = static_cast<int>(f.robot.joint_names.size());
  h.model_hash = f.robot.model_hash;
  h.control_period = 0.005;
  for (int j = 0; j < h.njoint; ++j)
    std::strncpy(h.joint_names[j], f.robot.joint_names[j].c_str(), shm::kNameLen - 1);
  return h;
}

// position commands for every joint at q
void Command(const double* q, int n, shm::CommandBlock* c) {
  c->njoint = n;
  for (int j = 0; j < n; ++j) c->joint[j] = {shm::JointMode::kPosition, 0, q[j], 0, 0, 100, 1};
}

class GuardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(collision::ReadSelfCollisionFile(kFile, &file_, &error)) << error;
    header_ = Header(file_);
    ASSERT_EQ(guard_.Configure(kFile, header_), "");
    sensors_ = shm::SensorBlock{};
    guard_.Activate(sensors_);  // the zero posture: arms hanging
  }
  collision::SelfCollisionFile file_;
  shm::SegmentHeader header_;
  shm::SensorBlock sensors_;
  shm::CommandBlock commands_{};
  SelfCollisionGuard guard_;
};

TEST_F(GuardTest, HoldsTheArmSwungIntoTheLegAndNamesThePair) {
  double q[shm::kMaxJoints] = {};
  // the right arm rolled inwards to its limit: the hand is in the thigh
  q[kRarmShoulderR] = 0.2618;
  q[kRarmElbow] = 0.0;
  Command(q, header_.njoint, &commands_);
  EXPECT_TRUE(guard_.Filter(sensors_, &commands_));
  EXPECT_EQ(commands_.joint[kRarmShoulderR].q_ref, 0.0);  // the last safe reference
  EXPECT_EQ(guard_.held_cycles(), 1);
  std::ostringstream out;
  guard_.Report("test", out);
  EXPECT_NE(out.str().find("held the last safe references in 1 cycles"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("RARM_"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("RLEG_"), std::string::npos) << out.str();
}

TEST_F(GuardTest, LetsSafeMotionAndMovingAwayThrough) {
  double q[shm::kMaxJoints] = {};
  q[kRarmShoulderR] = -0.5;  // outwards
  Command(q, header_.njoint, &commands_);
  EXPECT_FALSE(guard_.Filter(sensors_, &commands_));
  EXPECT_EQ(commands_.joint[kRarmShoulderR].q_ref, -0.5);
  EXPECT_EQ(guard_.held_cycles(), 0);
  std::ostringstream out;
  guard_.Report("test", out);
  EXPECT_EQ(out.str(), "");
}

TEST_F(GuardTest, RefusesAFileForAnotherRobot) {
  shm::SegmentHeader other = header_;
  other.model_hash ^= 1;
  SelfCollisionGuard g;
  EXPECT_NE(g.Configure(kFile, other).find("regenerate it with ohrp_selfcollision"), std::string::npos);
  EXPECT_FALSE(SelfCollisionGuard::FileMatches(kFile, other));
  other = header_;
  std::strcpy(other.joint_names[3], "ELSEWHERE");
  EXPECT_NE(g.Configure(kFile, other).find("joint 3 is RLEG_KNEE, the segment's is ELSEWHERE"),
            std::string::npos);
}

#ifdef OHRP_CAN_COUNT
TEST_F(GuardTest, ACycleAllocatesNothing) {
  double q[shm::kMaxJoints] = {};
  q[kRarmShoulderR] = 0.2618;
  q[0] = 0.7;  // a leg out of nothing's way, the arm into the leg: both paths of the check
  Command(q, header_.njoint, &commands_);
  EXPECT_EQ(ohrp::testing::Allocations([&] { guard_.Filter(sensors_, &commands_); }), 0);
  q[kRarmShoulderR] = -0.3;
  Command(q, header_.njoint, &commands_);
  EXPECT_EQ(ohrp::testing::Allocations([&] { guard_.Filter(sensors_, &commands_); }), 0);
}
#endif

}  // namespace
}  // namespace ohrp::controllers
