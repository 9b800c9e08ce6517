// Tests the walk controller in-process on HRP-1S (sim_host::InProcessRobot: soft soles, 1 ms
// physics, 5 ms control), judged on the simulation's truth: a velocity walk stopped mid-way
// (SIGUSR1's request) ends standing with the feet side by side, fewer steps than planned and
// the later commands dropped; a `wait` between two goals holds the robot still.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "controllers/walk.h"
#include "sim_host/in_process.h"

namespace ohrp::controllers {
namespace {

constexpr double kWidth = 0.18;  // HRP-1S's soles side by side, centre to centre [m]

struct Loop {
  std::unique_ptr<sim::InProcessRobot> robot;
  std::unique_ptr<WalkController> walk;
  shm::CommandBlock commands{};

  explicit Loop(const std::vector<std::string>& lines) {
    sim::InProcessOptions io;
    io.scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
    io.keyframe = "halfsit";
    std::string error;
    robot = sim::InProcessRobot::Create(io, &error);
    EXPECT_TRUE(robot) << error;
    WalkOptions o;
    o.balance.ramp = 0.5;
    for (const std::string& line : lines) {
      WalkCommand c;
      EXPECT_TRUE(ParseWalkCommand(line, &c, &error)) << error;
      o.commands.push_back(c);
    }
    ConfigStatus status;
    walk = WalkController::Create(o, &status);
    EXPECT_TRUE(walk) << status.message;
    if (!robot || !walk) return;
    status = walk->configure(robot->header());
    EXPECT_TRUE(status.ok()) << status.message;
    walk->activate(robot->sensors());
  }
  void Cycle() {
    walk->update(robot->sensors(), &commands);
    robot->Cycle(commands);
  }
  double time() const { return robot->sensors().time; }
  // a sole's centre in the world (truth) [m]
  Eigen::Vector3d Sole(const char* name) const {
    const int g = mj_name2id(robot->m(), mjOBJ_GEOM, name);
    const double* p = robot->d()->geom_xpos + 3 * g;
    return Eigen::Vector3d(p[0], p[1], p[2]);
  }
  double BaseHeight() const { return robot->d()->qpos[2]; }
};

TEST(WalkStop, AVelocityWalkStopsOnBothFeet) {
  Loop l({"velocity 0.2 0 0 20", "goal 1 0 0"});
  ASSERT_TRUE(l.walk);
  // walk until 4 steps have landed, then ask for the stop
  while (l.walk->walk_stats().steps_done < 4 && l.time() < 20) l.Cycle();
  ASSERT_GE(l.walk->walk_stats().steps_done, 4);
  WalkController::RequestWalkStop();
  for (int i = 0; i < 800; ++i) l.Cycle();  // 4 s
  const WalkStats& s = l.walk->walk_stats();
  EXPECT_TRUE(s.stopped);
  EXPECT_TRUE(l.walk->done());
  EXPECT_LE(s.steps_done, 7);  // the step in the air, the next, and the closing step at most
  EXPECT_LT(s.steps_done, s.steps_planned);
  // the feet side by side: the same x, the soles' width apart (truth, 2 cm)
  const Eigen::Vector3d left = l.Sole("LLEG_SOLE"), right = l.Sole("RLEG_SOLE");
  EXPECT_LT(std::abs(left.x() - right.x()), 0.02);
  EXPECT_NEAR(left.y() - right.y(), kWidth, 0.02);
  EXPECT_GT(l.BaseHeight(), 0.6);  // standing
}

TEST(WalkStop, AWaitHoldsBetweenTwoGoals) {
  Loop l({"goal 0.5 0 0", "wait 2", "goal 0.5 0 0"});
  ASSERT_TRUE(l.walk);
  // the first goal done (its steps landed), then the wait: the base stays within 1 cm for 1.5 s
  const int first = static_cast<int>(l.walk->chunks()[0].size());
  while (l.walk->walk_stats().steps_done < first && l.time() < 20) l.Cycle();
  for (int i = 0; i < 200; ++i) l.Cycle();  // the ZMP back between the feet
  const double x0 = l.robot->d()->qpos[0];
  for (int i = 0; i < 200; ++i) l.Cycle();
  EXPECT_NEAR(l.robot->d()->qpos[0], x0, 0.01);
  while (!l.walk->done() && l.time() < 40) l.Cycle();
  EXPECT_TRUE(l.walk->done());
  EXPECT_EQ(l.walk->walk_stats().commands_done, 3);
  EXPECT_NEAR(l.robot->d()->qpos[0], 1.0, 0.15);  // both goals walked (the base 6 cm ahead)
}

}  // namespace
}  // namespace ohrp::controllers
