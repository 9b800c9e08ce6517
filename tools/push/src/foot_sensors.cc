// The soles' F/T sensors of a scene's robot, from its model: what the standing judgement reads.
#include <mujoco/mujoco.h>

#include "push/push.h"
#include "robot_model/kinematics.h"
#include "robot_model/load.h"
#include "robot_model/model.h"

namespace ohrp::push {

bool FootSensorsOf(const std::string& scene, std::vector<std::string>* names, std::string* error) {
  model::ModelPtr m(model::LoadMujocoModel(scene, error));
  if (!m) return false;
  model::RobotMap robot;
  if (!model::MapRobot(m.get(), &robot, error)) return false;
  names->clear();
  for (const model::SoleMap& sole : model::FindSoles(m.get(), robot))
    if (sole.force_sensor >= 0) names->push_back(robot.forces[sole.force_sensor].name);
  if (names->empty()) {
    *error = scene + ": no sole of the robot has a force/torque sensor (soles: box geoms named "
                     "*_SOLE or a robot profile's feet; or give --foot-sensors)";
    return false;
  }
  return true;
}

}  // namespace ohrp::push
