// sim_host's names for the robot model of the lower layer (robot_model/): the simulator loads
// the scene, maps the robot, reads the sensors and runs the joint servos with the same code as
// hw_driver, its emulator and the controllers.
#pragma once

#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

using model::CameraMap;
using model::DescribeActuation;
using model::FillSensors;
using model::ForceSensorMap;
using model::ImuMap;
using model::InstallMujocoHandlers;
using model::JointMap;
using model::kMaxGain;
using model::kNoLimit;
using model::kRangeTolerance;
using model::LastWarning;
using model::MakeProducerConfig;
using model::MapRobot;
using model::RobotMap;
using model::Scene;
using model::SensorSelection;
using model::Servo;
using model::WarningCount;

}  // namespace ohrp::sim
