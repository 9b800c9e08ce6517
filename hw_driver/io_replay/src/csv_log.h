// The producers' CSV data log (datalog/recorder.h, read by datalog::Table) for the replay plugin: the columns a
// RobotIo needs (joint positions and torques, force/torque sensors, IMUs), looked up by name,
// joint velocities by finite differences, and linear interpolation or steps in time.
#pragma once

#include <string>
#include <vector>

#include "hw_driver/robot_io.h"

namespace ohrp::hw::replay {

class CsvLog {
 public:
  // Reads `path` for the joints and sensors named in `config`. Every joint needs a q_<joint>
  // column; tau_<joint>, the F/T (<ft>_fx..), IMU (<imu>_gx..) and passive joint (q_<passive>,
  // dq_<passive>) columns are optional (zero, identity quaternion; a passive joint's missing
  // velocity by differences). Times must increase strictly. False with `*error` naming the file
  // (and the line) on failure.
  bool Load(const std::string& path, const IoConfig& config, std::string* error);

  int rows() const { return static_cast<int>(time_.size()); }
  double first_time() const { return time_.front(); }
  double last_time() const { return time_.back(); }

  // Fills q, dq, tau, force, imu, passive_q, passive_dq of `*state` at log time `t` (clamped to the log's span),
  // interpolated linearly between rows (`step`: the last row at or before t). `cursor` is a
  // row hint kept by the caller for monotone playback. Never allocates.
  void Sample(double t, bool step, int* cursor, IoState* state) const;

 private:
  int njoint_ = 0, nforce_ = 0, nimu_ = 0, npassive_ = 0, width_ = 0;
  std::vector<double> time_;
  std::vector<double> data_;  // rows x width_: q, dq, tau (njoint each), F/T (6), IMU (10),
                              // passive q, dq (npassive each)
};

}  // namespace ohrp::hw::replay
