// The data log's column names of a robot (log_names.h).
#include "robot_model/log_names.h"

namespace ohrp::model {

datalog::LogNames LogNamesOf(const RobotMap& robot) {
  datalog::LogNames n;
  for (const auto& j : robot.joints) n.joints.push_back(j.name);
  for (const auto& f : robot.forces) n.forces.push_back(f.name);
  for (const auto& u : robot.imus) n.imus.push_back(u.name);
  for (const auto& p : robot.passive) n.passive.push_back(p.name);
  return n;
}

}  // namespace ohrp::model
