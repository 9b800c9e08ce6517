// The robot's sensors as the segment carries them, computed from MuJoCo's state.
#pragma once

#include "shm_bridge/bridge.h"
#include "robot_model/model.h"
#include "robot_model/sensor_params.h"

namespace ohrp::model {

// The segment's description of `robot` (names, limits, default gains, cameras, periods, and the
// model identity: model_hash, masses and axes, see model_hash.h).
shm::ProducerConfig MakeProducerConfig(const RobotMap& robot, const mjModel* m,
                                       const std::string& segment_name, double physics_period,
                                       double control_period);

// Fills the measurement part of `*out` (q, dq, tau, force/torque, IMU, ground truth) from the
// state in `d` after mj_step (sensordata is current). Does not touch cycle, time, status or
// counters. Never allocates.
void FillSensors(const RobotMap& robot, const mjModel* m, const mjData* d, shm::SensorBlock* out);

// Which of the segment's sensor fields are measured (see sim_host/effects.h: SelectSensors).
struct SensorSelection {
  bool q = true, dq = true, tau = true, force_torque = true, gyro = true, accel = true,
       orientation = true;
};

// The same for the sensor kinds `selection` switches on; the fields of the kinds that are off
// are set to NaN (not measured) and their MuJoCo sensors are not read.
void FillSensors(const RobotMap& robot, const mjModel* m, const mjData* d,
                 const SensorSelection& selection, shm::SensorBlock* out);

// A sensor file's entries (ReadSensorParamsFile) bound to `robot`'s joints, IMUs and F/T sensors
// by name (BindSensorParams), in the robot's order. False with `*error` naming an entry the robot
// does not have.
bool BindSensorParams(const SensorParams& file, const RobotMap& robot, SensorParams* by_index,
                      std::string* error);

// The sensor model on a block FillSensors filled: each field `selection` measures gets its bias
// and noise; the others (NaN) stay as they are. One draw order (encoders, velocities, torques,
// F/T, IMUs), whoever calls it: sim_host on what it publishes, hw_emulator on what its boards
// report. Never allocates.
void ApplySensorModel(const RobotMap& robot, const SensorSelection& selection,
                      SensorModel* sensors, shm::SensorBlock* s) noexcept;

}  // namespace ohrp::model
