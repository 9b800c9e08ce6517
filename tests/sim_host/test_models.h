// Small inline MJCF models for the sim_host tests, written to scratch files (common/scratch.h).
#pragma once

#include <string>

#include "common/scratch.h"

namespace ohrp::sim::testing {

// A fixed base with one hinge joint whose motion is pure rotor inertia (armature) on a
// massless-looking link, plus a second hinge: the servo's closed-form test bed.
inline constexpr const char* kTwoJointArm = R"(
<mujoco model="arm">
  <compiler angle="radian"/>
  <option timestep="0.001" integrator="Euler" gravity="0 0 0"/>
  <worldbody>
    <body name="link1">
      <joint name="j1" type="hinge" axis="0 0 1" armature="2" limited="true" range="-1.5 1.5"/>
      <geom type="sphere" size="0.01" mass="1e-6" pos="0 0 0"/>
      <body name="link2" pos="0.1 0 0">
        <joint name="j2" type="hinge" axis="0 0 1" armature="1"/>
        <geom type="sphere" size="0.01" mass="1e-6"/>
        <site name="tip"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="j1" joint="j1" ctrllimited="true" ctrlrange="-50 50"/>
    <motor name="j2" joint="j2" ctrllimited="true" ctrlrange="-20 20"/>
  </actuator>
  <sensor>
    <force name="tip_f" site="tip"/>
    <torque name="tip_t" site="tip"/>
  </sensor>
</mujoco>
)";

// A box resting on a plane, actuated by nothing: a model the segment cannot carry.
inline constexpr const char* kNoMotors = R"(
<mujoco model="box">
  <worldbody>
    <geom type="plane" size="1 1 0.1"/>
    <body pos="0 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
</mujoco>
)";

// A motor with gear 2: sim_host's servo writes torques and refuses it.
inline constexpr const char* kGearedMotor = R"(
<mujoco model="geared">
  <worldbody>
    <body><joint name="j" type="hinge"/><geom type="sphere" size="0.1"/></body>
  </worldbody>
  <actuator><motor joint="j" gear="2"/></actuator>
</mujoco>
)";

inline constexpr const char* kFilteredActuator = R"(
<mujoco model="filtered">
  <worldbody>
    <body><joint name="j" type="hinge"/><geom type="sphere" size="0.1"/></body>
  </worldbody>
  <actuator><general joint="j" dyntype="filter" dynprm="0.05"/></actuator>
</mujoco>
)";

// Writes `text` to a fresh file in the test's scratch folder and returns its path.
inline std::string WriteTemp(const std::string& text, const std::string& suffix = ".xml") {
  return ohrp::testing::ScratchFile("model", text, suffix);
}

}  // namespace ohrp::sim::testing
