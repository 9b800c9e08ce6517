// Tests the controller lifecycle state machine and the command guard (controllers/controller.h).
#include "controllers/controller.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

namespace ohrp::controllers {
namespace {

// writes NaN to joint 0, an out-of-limit reference to joint 1, a good one to joint 2
class BadController : public Controller {
 public:
  bool fail_configure = false;
  int activations = 0;

 protected:
  ConfigStatus on_configure(const shm::SegmentHeader&) override {
    return fail_configure ? ConfigStatus::Fail(ConfigError::kMismatch, "no") : ConfigStatus::Ok();
  }
  void on_activate(const shm::SensorBlock&) noexcept override { ++activations; }
  void on_update(const shm::SensorBlock&, shm::CommandBlock* c) noexcept override {
    for (int j = 0; j < 3; ++j) {
      c->joint[j] = {shm::JointMode::kPosition, 0, 0.5, 0.0, 0.0, 10.0, 1.0};
    }
    c->joint[0].q_ref = std::numeric_limits<double>::quiet_NaN();
    c->joint[1].q_ref = 5.0;
  }
};

shm::SegmentHeader Header() {
  shm::SegmentHeader h{};
  h.njoint = 3;
  for (int j = 0; j < 3; ++j) {
    std::snprintf(h.joint_names[j], shm::kNameLen, "J%d", j);
    h.q_min[j] = -1.0;
    h.q_max[j] = 1.0;
    h.default_kp[j] = 7.0;
    h.default_kd[j] = 0.7;
  }
  return h;
}

TEST(ControllerTest, TransitionsFollowTheStateMachine) {
  BadController c;
  shm::SensorBlock s{};
  shm::CommandBlock cmd{};
  EXPECT_FALSE(c.activate(s));           // not configured
  EXPECT_FALSE(c.update(s, &cmd));
  c.fail_configure = true;
  EXPECT_EQ(c.configure(Header()).code, ConfigError::kMismatch);
  EXPECT_EQ(c.state(), LifecycleState::kUnconfigured);
  c.fail_configure = false;
  ASSERT_TRUE(c.configure(Header()).ok());
  EXPECT_EQ(c.state(), LifecycleState::kInactive);
  EXPECT_EQ(c.joint_names(), (std::vector<std::string>{"J0", "J1", "J2"}));
  EXPECT_EQ(c.configure(Header()).code, ConfigError::kState);
  EXPECT_FALSE(c.update(s, &cmd));       // not active
  EXPECT_TRUE(c.activate(s));
  EXPECT_FALSE(c.close());               // deactivate first
  EXPECT_TRUE(c.update(s, &cmd));
  EXPECT_TRUE(c.deactivate());
  EXPECT_EQ(c.state(), LifecycleState::kInactive);
  EXPECT_TRUE(c.close());
  EXPECT_EQ(c.state(), LifecycleState::kClosed);
  EXPECT_FALSE(c.activate(s));
  EXPECT_EQ(c.activations, 1);
}

TEST(ControllerTest, GuardHoldsNonFiniteAndClampsToLimits) {
  BadController c;
  ASSERT_TRUE(c.configure(Header()).ok());
  shm::SensorBlock s{};
  s.q[0] = 0.25;
  ASSERT_TRUE(c.activate(s));
  shm::CommandBlock cmd{};
  ASSERT_TRUE(c.update(s, &cmd));
  EXPECT_EQ(cmd.njoint, 3);
  EXPECT_DOUBLE_EQ(cmd.joint[0].q_ref, 0.25);  // held at the activation pose
  EXPECT_DOUBLE_EQ(cmd.joint[0].kp, 7.0);      // with the default gains
  EXPECT_DOUBLE_EQ(cmd.joint[1].q_ref, 1.0);   // clamped to q_max
  EXPECT_DOUBLE_EQ(cmd.joint[2].q_ref, 0.5);   // untouched
  EXPECT_EQ(c.counters().non_finite_fixed, 1u);
  EXPECT_EQ(c.counters().clamped, 1u);
  EXPECT_EQ(c.counters().updates, 1u);
}

}  // namespace
}  // namespace ohrp::controllers
