// The effects tests' scenes and helpers: HRP-1S on the flat floor, a pendulum, free boxes and a
// two-link arm whose links may touch; a scene loaded with its robot map, a plan resolved from an
// --effects spec (or the error of one that must be refused) and applied to the model. Used by
// effects_test.cc, effects_off_test.cc and effects_process_test.cc.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "sim_host/effects.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "test_models.h"

namespace ohrp::sim::testing {

inline const std::string kFlat = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";

// a hinge pendulum with a motor, no sensors, no soles, a camera-less scene
inline constexpr const char* kPendulum = R"(
<mujoco model="pendulum">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler"/>
  <worldbody>
    <body name="link">
      <joint name="j" type="hinge" axis="0 1 0"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.5" size="0.02" mass="1" contype="0" conaffinity="0"/>
    </body>
  </worldbody>
  <actuator><motor name="j" joint="j" ctrllimited="true" ctrlrange="-10 10"/></actuator>
</mujoco>
)";

// two free boxes above a floor, and a two-link robot whose links may touch each other
inline constexpr const char* kBoxes = R"(
<mujoco model="boxes">
  <compiler angle="radian"/>
  <option timestep="0.002" integrator="Euler"/>
  <worldbody>
    <geom name="floor" type="plane" size="5 5 0.1"/>
    <body name="box1" pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    <body name="box2" pos="1 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1" mass="1"/></body>
    <body name="arm" pos="3 0 1">
      <joint name="a1" type="hinge" axis="0 1 0"/>
      <geom type="sphere" size="0.05" pos="0.3 0 0" mass="1"/>
      <body name="forearm" pos="0.6 0 0">
        <joint name="a2" type="hinge" axis="0 1 0"/>
        <geom type="sphere" size="0.05" pos="-0.3 0 0" mass="1"/>
        <body name="hand">
          <joint name="a3" type="hinge" axis="0 1 0"/>
          <geom type="sphere" size="0.05" pos="-0.3 0 0.02" mass="1"/>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="a1"/><motor joint="a2"/><motor joint="a3"/></actuator>
</mujoco>
)";

struct Loaded {
  std::unique_ptr<model::Scene> scene;
  model::RobotMap robot;
};

inline Loaded Load(const std::string& path) {
  Loaded l;
  std::string error;
  l.scene = model::Scene::Load(path, &error);
  EXPECT_TRUE(l.scene) << error;
  EXPECT_TRUE(model::MapRobot(l.scene->m(), &l.robot, &error)) << error;
  return l;
}

inline Loaded LoadText(const char* xml) { return Load(testing::WriteTemp(xml)); }

inline EffectsPlan Resolve(const Loaded& l, const std::string& spec, bool log = false,
                    ContactModel contact = ContactModel::kAuto) {
  EffectRequests req;
  std::string error;
  EXPECT_TRUE(ParseEffectRequests(spec, &req, &error)) << error;
  FeetOptions feet;
  feet.model = contact;
  EffectsPlan plan;
  EXPECT_TRUE(ResolveEffects(l.scene->m(), l.robot, feet, log, req, &plan, &error)) << error;
  return plan;
}

// the error of a resolution that must fail
inline std::string Refused(const Loaded& l, const std::string& spec, bool log = false) {
  EffectRequests req;
  std::string error;
  if (!ParseEffectRequests(spec, &req, &error)) return error;
  EffectsPlan plan;
  EXPECT_FALSE(ResolveEffects(l.scene->m(), l.robot, FeetOptions{}, log, req, &plan, &error))
      << spec << " was accepted";
  return error;
}

// applies the plan to the model and resets it (Reset runs mj_forward)
inline void Apply(const Loaded& l, const EffectsPlan& p) {
  ApplyEffects(p, l.robot, l.scene->m());
  std::string error;
  ASSERT_TRUE(l.scene->Reset("", &error)) << error;
}

}  // namespace ohrp::sim::testing
