// The data log's column names of a robot (datalog/recorder.h: LogNames), in the segment's order:
// its joints, force/torque sensors, IMUs and passive joints from the robot map.
#pragma once

#include "datalog/recorder.h"
#include "robot_model/model.h"

namespace ohrp::model {

datalog::LogNames LogNamesOf(const RobotMap& robot);

}  // namespace ohrp::model
