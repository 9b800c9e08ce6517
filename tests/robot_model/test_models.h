// Models shared by the robot_model tests: a planar two-link arm written inline, and HRP-1S.
#pragma once

#include <mujoco/mujoco.h>

#include <cstring>
#include <memory>
#include <string>

#include "robot_model/kinematics.h"

namespace ohrp::model::testing {

// the planar arm: two links along x turning about z, gravity along -y
inline constexpr double kL1 = 1.0, kLc1 = 0.4, kM1 = 2.0, kI1 = 0.06, kA1 = 0.3;  // [m, m, kg, kg m^2, kg m^2]
inline constexpr double kL2 = 0.8, kLc2 = 0.3, kM2 = 1.5, kI2 = 0.04, kA2 = 0.2;
inline constexpr double kG = 9.81;  // [m/s^2]
inline constexpr char kArm[] = R"(
<mujoco model="arm">
  <compiler angle="radian"/>
  <option gravity="0 -9.81 0"/>
  <worldbody>
    <body name="link1">
      <joint name="j1" type="hinge" axis="0 0 1" armature="0.3" limited="true" range="-3.1 3.1"/>
      <inertial pos="0.4 0 0" mass="2" diaginertia="0.01 0.05 0.06"/>
      <body name="link2" pos="1 0 0">
        <joint name="j2" type="hinge" axis="0 0 1" armature="0.2" limited="true" range="-3.1 3.1"/>
        <inertial pos="0.3 0 0" mass="1.5" diaginertia="0.01 0.03 0.04"/>
        <site name="tip" pos="0.8 0 0"/>
      </body>
    </body>
  </worldbody>
  <actuator><motor joint="j1"/><motor joint="j2"/></actuator>
</mujoco>)";

// a model from MJCF text, through MuJoCo's virtual file system; null on failure
inline mjModel* LoadString(const char* xml, std::string* error) {
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const int size = static_cast<int>(std::strlen(xml));
  if (mj_makeEmptyFileVFS(vfs.get(), "model.xml", size) != 0) {
    *error = "cannot make the virtual file";
    return nullptr;
  }
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml, size);
  char err[512] = "";
  mjModel* m = mj_loadXML("model.xml", vfs.get(), err, sizeof(err));
  mj_deleteVFS(vfs.get());
  if (!m) *error = err;
  return m;
}

inline std::unique_ptr<Kinematics> Arm(std::string* error) {
  mjModel* m = LoadString(kArm, error);
  if (!m) return nullptr;
  auto kin = Kinematics::FromModel(m, error);
  mj_deleteModel(m);
  return kin;
}

inline std::unique_ptr<Kinematics> Hrp1s(std::string* error) {
  return Kinematics::Load(std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml", error);
}

}  // namespace ohrp::model::testing
