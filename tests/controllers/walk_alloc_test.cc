// Tests that the walk controller's per-cycle path allocates nothing (issue 10, item 3): the
// controller stepped in-process (sim_host::InProcessRobot: soft soles, 1 ms physics, 5 ms
// control) through standing up and a 1 m walk with its CSV log on; every heap allocation made
// inside update() is counted (this binary replaces malloc: count_allocations.h). A binary of its
// own, like robot_model_alloc_test.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include "../robot_model/count_allocations.h"
#include "controllers/walk.h"
#include "fake_robot.h"
#include "sim_host/in_process.h"

namespace ohrp::controllers::testing {
namespace {

#if defined(OHRP_CAN_COUNT)

using ohrp::testing::Allocations;

constexpr double kLimit = 30.0;  // [s] of robot time the walk must be done in

// allocations inside update(), by phase, and the first cycle that allocated while walking
struct Count {
  long standing = 0, walking = 0, after = 0;
  double first_at = -1;  // producer time [s]
  int first_step = -1;   // steps landed then
};

// a 1 m walk; with `stepping`, the stepping strategy on and a push from the side at `push_at`
// (0.1 s, `impulse` N s towards -y) that makes it move a landing; with `late`, touchdown on and
// 0.3 m steps off an unseen 3 cm step down (late touchdowns: the landing held, the foot on down);
// with `early`, onto an unseen 3 cm step up (early touchdowns: the swing ended, the plan re-based)
void WalksWithoutAllocating(bool stepping, double push_at, double impulse, bool late = false,
                            bool early = false) {
  sim::InProcessOptions io;
  io.scene = std::string(OHRP_SOURCE_DIR) +
             (late    ? "/mjcf/hrp1s/scene_unseen_step_down.xml"
              : early ? "/mjcf/hrp1s/scene_unseen_step_up.xml"
                      : "/mjcf/hrp1s/scene_flat.xml");
  io.keyframe = "halfsit";
  if (stepping) {
    sim::Perturbation push;
    push.t0 = push_at;
    push.t1 = push_at + 0.1;
    push.force[1] = -impulse / 0.1;
    io.pushes.push_back(push);
  }
  std::string error;
  auto robot = sim::InProcessRobot::Create(io, &error);
  ASSERT_TRUE(robot) << error;
  // a 1 m walk with the log kept in memory (written at close)
  const std::string log = TempPath("walk_alloc_log");
  WalkOptions o;
  o.balance.ramp = 0.5;
  o.balance.load_feedforward = 1;  // its gravity torques and Jacobians run in the cycle too
  WalkCommand goal;
  const std::string command =
      late    ? "steps " + std::string(OHRP_SOURCE_DIR) + "/scenarios/steps/unseen_step_down.yaml"
      : early ? "steps " + std::string(OHRP_SOURCE_DIR) + "/scenarios/steps/unseen_step_up.yaml"
              : std::string("goal 1 0 0");
  ASSERT_TRUE(ParseWalkCommand(command, &goal, &error)) << error;
  o.commands.push_back(goal);
  if (late || early) {
    o.touchdown = true;
    o.limits.max_forward = 0.3;
  }
  o.log_file = log;
  o.stepping = stepping;
  ConfigStatus status;
  auto walk = WalkController::Create(o, &status);
  ASSERT_TRUE(walk) << status.message;
  status = walk->configure(robot->header());
  ASSERT_TRUE(status.ok()) << status.message;
  walk->activate(robot->sensors());

  // the counter works in this binary
  std::unique_ptr<double[]> probe;
  ASSERT_GT(Allocations([&] { probe = std::make_unique<double[]>(64); }), 0);

  // the control loop: only update() is counted
  shm::CommandBlock commands{};
  Count n;
  bool was_walking = false;
  while (robot->sensors().time < kLimit && !(was_walking && walk->done())) {
    const shm::SensorBlock& s = robot->sensors();
    const long k = Allocations([&] { walk->update(s, &commands); });
    was_walking = was_walking || walk->walking();
    long& phase = !was_walking ? n.standing : walk->done() ? n.after : n.walking;
    phase += k;
    if (k > 0 && was_walking && n.first_at < 0) {
      n.first_at = s.time;
      n.first_step = walk->walk_stats().steps_done;
    }
    robot->Cycle(commands);
  }
  ASSERT_TRUE(walk->deactivate());
  ASSERT_TRUE(walk->close());
  std::ostringstream report;
  walk->report(report);
  const WalkStats& w = walk->walk_stats();
  std::printf("[ figures  ] allocations in update(): %ld standing up, %ld walking (first at "
              "t = %.3f s, %d steps landed), %ld after; %d steps, %llu walk cycles from %.3f s\n%s",
              n.standing, n.walking, n.first_at, n.first_step, n.after, w.steps_done,
              static_cast<unsigned long long>(w.walk_cycles), w.walk_start, report.str().c_str());
  // the walk was walked: several steps, all landed, done on both feet (off the unseen step
  // down: late touchdowns, the walk not yet done: docs/walking.md, "Not done")
  if (late) {
    EXPECT_GT(w.late_touchdowns + w.late_missed, 0) << report.str();  // the late path ran
  } else if (early) {
    EXPECT_GT(w.early_touchdowns, 0) << report.str();  // the early path ran
    // and found the platform's rise (the torso's pitch limited while the trailing foot left)
    EXPECT_GE(w.step_ups, 1) << report.str();
    EXPECT_LE(w.step_ups, w.early_touchdowns) << report.str();
  } else {
    EXPECT_TRUE(walk->done()) << report.str();
  }
  EXPECT_GE(w.steps_done, 4);
  if (!stepping && !late && !early) {  // stepping re-plans the steps
    EXPECT_EQ(w.steps_done, w.steps_planned);
  }
  EXPECT_EQ(n.walking, 0) << "heap allocations in WalkController::update while walking (first "
                             "at t = " << n.first_at << " s)";
  EXPECT_EQ(n.after, 0) << "heap allocations after the walk";
  EXPECT_TRUE(std::filesystem::file_size(log) > 0) << "the walk log written at close";
  if (stepping) {
    EXPECT_GT(w.steps_adjusted, 0) << "the push did not make the stepping strategy move a landing";
  }
  std::filesystem::remove(log);
}

TEST(WalkAllocation, UpdateAllocatesNothingOnceWalking) { WalksWithoutAllocating(false, 0, 0); }

// the stepping strategy's cycle (landing and timing chosen, the plan's later steps replaced)
TEST(WalkAllocation, TheSteppingStrategyAllocatesNothing) { WalksWithoutAllocating(true, 4.5, 50); }

// a late touchdown's cycle (the landing and the later steps delayed, the foot and the CoM on down)
TEST(WalkAllocation, ALateTouchdownAllocatesNothing) { WalksWithoutAllocating(false, 0, 0, true); }

// an early touchdown's cycle (the swing ended, the later steps re-timed, the plan re-based)
TEST(WalkAllocation, AnEarlyTouchdownAllocatesNothing) {
  WalksWithoutAllocating(false, 0, 0, false, true);
}

#else
TEST(WalkAllocation, NeedsTheCounter) {
  GTEST_SKIP() << "heap allocations cannot be counted in this build (count_allocations.h)";
}
#endif

}  // namespace
}  // namespace ohrp::controllers::testing
