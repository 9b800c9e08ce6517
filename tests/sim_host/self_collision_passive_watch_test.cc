// sim_host's self_collision effect on a robot with a passive joint (no actuator: Cassie's shins,
// tarsi, springs): the watch poses the links with the simulated passive angles too. A torso with
// a sphere on an actuated hinge (the post, radius 0.05 m, 0.5 m out along x) and a sphere on a
// passive hinge about z (the arm, radius 0.06 m, 0.4 m out, ref 0.3 rad): at angle q the arm's
// centre is 0.4 (cos q, sin q), so the pair's signed distance is |(0.5, 0) - 0.4 (cos q, sin q)|
// - 0.11: apart at the reference (57 mm), 10 mm deep at q = 0.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>

#include "common/scratch.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "sim_host/self_collision_watch.h"

namespace ohrp::sim {
namespace {

constexpr char kXml[] = R"(<mujoco model="passive">
  <compiler angle="radian"/>
  <worldbody>
    <body name="torso" pos="0 0 1"><freejoint/>
      <geom type="box" size=".02 .02 .02"/>
      <body name="post" pos=".5 0 0">
        <joint name="lift" axis="0 1 0" limited="true" range="-1 1"/>
        <geom type="sphere" size=".05"/>
      </body>
      <body name="arm" axisangle="0 0 1 0.3">
        <joint name="swing" axis="0 0 1" ref="0.3" limited="true" range="-1.2 1.2"/>
        <geom type="sphere" size=".06" pos=".4 0 0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="lift"/></actuator>
</mujoco>)";

double Closed(double q) {
  return std::hypot(0.5 - 0.4 * std::cos(q), 0.4 * std::sin(q)) - 0.11;
}

TEST(SelfCollisionWatchPassive, ThePassiveAngleMovesTheLinkIntoContact) {
  model::InstallMujocoHandlers(nullptr);
  const std::string path = ohrp::testing::ScratchFile("passive", kXml, ".xml");
  std::string error;
  auto scene = model::Scene::Load(path, &error);
  ASSERT_TRUE(scene) << error;
  model::RobotMap robot;
  ASSERT_TRUE(model::MapRobot(scene->m(), &robot, &error)) << error;
  ASSERT_EQ(robot.passive.size(), 1u);
  auto w = SelfCollisionWatch::Create(scene->m(), robot, "", &error);
  ASSERT_TRUE(w) << error;
  mjData* d = scene->d();
  const int swing = robot.passive[0].qpos_adr;
  // the start, at the reference: apart, nothing left out
  w->Start(d);
  w->Check(d, 0.0, 0);
  EXPECT_EQ(w->Summary().pairs.size(), 0u);
  EXPECT_GT(Closed(0.3), 0.05);
  // only the passive angle moves: into contact as the closed form says, then out again
  for (int k = 1; k <= 30; ++k) {
    d->qpos[swing] = 0.3 - 0.01 * k;  // down to 0: 10 mm deep
    w->Check(d, 0.005 * k, k);
  }
  d->qpos[swing] = 1.0;
  w->Check(d, 0.2, 31);
  const SelfCollisionSummary s = w->Summary();
  ASSERT_EQ(s.pairs.size(), 1u);
  EXPECT_EQ(s.pairs[0].pair, "post/arm");
  EXPECT_NEAR(s.pairs[0].deepest, -Closed(0.0), 1e-6);
  EXPECT_NEAR(s.pairs[0].deepest, 0.01, 1e-6);
  // in contact from the first angle whose closed form is negative, to q = 0
  int first = 0, in_contact = 0;
  for (int k = 1; k <= 30; ++k)
    if (Closed(0.3 - 0.01 * k) < 0) in_contact += 1, first = first ? first : k;
  EXPECT_EQ(s.pairs[0].first_cycle, static_cast<uint64_t>(first));
  EXPECT_EQ(s.pairs[0].cycles, static_cast<uint64_t>(in_contact));
  EXPECT_GT(in_contact, 5);
}

}  // namespace
}  // namespace ohrp::sim
