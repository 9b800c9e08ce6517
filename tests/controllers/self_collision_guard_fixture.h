// The fixtures of the online self-collision check's tests (self_collision_guard_test.cc,
// self_collision_guard_leg_test.cc): HRP-1S's shipped file, its header, position commands.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "controllers/self_collision_guard.h"

namespace ohrp::controllers::guard_testing {

inline const std::string kFile = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/selfcollision.yaml";
constexpr int kRarmShoulderR = 7, kRarmElbow = 9;

// the header of HRP-1S as the file describes it; every joint's torque limit 200 N m
inline shm::SegmentHeader Header(const collision::SelfCollisionFile& f) {
  shm::SegmentHeader h{};
  h.njoint = static_cast<int>(f.robot.joint_names.size());
  h.model_hash = f.robot.model_hash;
  h.control_period = 0.005;
  std::strncpy(h.robot_name, f.robot.name.c_str(), sizeof(h.robot_name) - 1);
  for (int j = 0; j < h.njoint; ++j) {
    std::strncpy(h.joint_names[j], f.robot.joint_names[j].c_str(), shm::kNameLen - 1);
    h.tau_max[j] = 200;
    h.default_kp[j] = 100;
    h.default_kd[j] = 1;
  }
  return h;
}

// position commands for every joint at q
inline void Command(const double* q, int n, shm::CommandBlock* c) {
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
    guard_.Activate(sensors_);  // the zero posture: arms hanging beside the thighs
    Measure(&guard_);
  }
  // the first cycle after Activate only measures (the load is unknown until an acceleration
  // has been measured): the command is replaced by the brake from the measured state, which is
  // not a hold; the test's own command is kept for the next cycle
  void Measure(SelfCollisionGuard* g) {
    const shm::CommandBlock saved = commands_;
    EXPECT_TRUE(g->Filter(sensors_, &commands_));
    EXPECT_FALSE(g->holding());
    EXPECT_EQ(g->holds(), 0u);
    commands_ = saved;
  }
  collision::SelfCollisionFile file_;
  shm::SegmentHeader header_;
  shm::SensorBlock sensors_;
  shm::CommandBlock commands_{};
  SelfCollisionGuard guard_;
};

// A leg with a foot is braked while its foot carries no load (docs/selfcollision.md, "A leg
// whose foot is in the air"): the header names the feet's F/T sensors; the right hip rolls
// inwards at 3 rad/s from the zero posture (feet side by side) into the left leg. Feet in the
// air (0 N): the leg is braked along a ramp. Both feet loaded (half the weight each): never
// braked, the command kept (monitored). The load's hysteresis: loaded above the file's
// support_force (a tenth of the weight), unloaded below half of it, unchanged between.
class LegGuardTest : public GuardTest {
 protected:
  static constexpr int kRlegHipR = 0, kLlegHipR = 13;
  void SetUp() override {
    std::string error;
    ASSERT_TRUE(collision::ReadSelfCollisionFile(kFile, &file_, &error)) << error;
    header_ = Header(file_);
    header_.nforce = 2;
    std::strncpy(header_.force_names[0], "rfsensor", shm::kNameLen - 1);
    std::strncpy(header_.force_names[1], "lfsensor", shm::kNameLen - 1);
    ASSERT_EQ(file_.dynamics[kRlegHipR].support_sensor, "rfsensor");
    ASSERT_EQ(file_.dynamics[kLlegHipR].support_sensor, "lfsensor");
    on_ = file_.dynamics[kRlegHipR].support_force;
    sensors_ = shm::SensorBlock{};
  }
  void Feet(double fz) {
    for (int f = 0; f < 2; ++f) sensors_.force[f].force[2] = fz;
  }
  // configured and activated with the right hip rolling inwards at 3 rad/s, the command holding
  // the zero posture; true when the guard replaced the command in the cycle after measuring
  bool Swing(SelfCollisionGuard* g) {
    EXPECT_EQ(g->Configure(kFile, header_), "");
    double q[shm::kMaxJoints] = {};
    Command(q, header_.njoint, &commands_);
    sensors_.dq[kRlegHipR] = 3.0;
    g->Activate(sensors_);
    Measure(g);
    return g->Filter(sensors_, &commands_);
  }
  double on_ = 0;
};

}  // namespace ohrp::controllers::guard_testing
