// The data log of a producer (sim_host --log, hw_driver --log): one CSV row per recorded control
// cycle, written by a background thread from a preallocated ring, so the simulation loop or the
// driver's servo cycle never formats, allocates or blocks on disk. Both producers write the same
// format with the same column names; runner::Table (tools/runner/include/runner/checks.h) reads
// it back.
//
// Columns (first line of the file; SI units, angles in rad):
//   time, base_x, base_y, base_z, base_qw, base_qx, base_qy, base_qz,   (simulation ground truth:
//   base_vx, base_vy, base_vz,                                           sim_host only)
//   q_<joint>... , qref_<joint>... , tau_<joint>...                      (joint-id order)
//   <ft>_fx, <ft>_fy, <ft>_fz, <ft>_tx, <ft>_ty, <ft>_tz ...             (segment convention)
//   <imu>_gx, <imu>_gy, <imu>_gz, <imu>_ax, <imu>_ay, <imu>_az,
//   <imu>_qw, <imu>_qx, <imu>_qy, <imu>_qz ...
//   status, rejected
// The channels (base, joints, F/T, IMU) can be left out (RecorderChannels, the log_* effects of
// sim_host/effects.h); time, status and rejected are always there. hw_driver has no ground
// truth: its logs have no base_* columns (base = false), the sensor channels are the same.
// qref_ is the reference the servos held over the interval that ends at the row's time.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "shm_bridge/layout.h"
#include "robot_model/model.h"

namespace ohrp::model {

// which column groups the log has
struct RecorderChannels {
  bool base = true;          // base_x ... base_vz
  bool joints = true;        // q_, qref_, tau_
  bool force_torque = true;  // <ft>_fx ... <ft>_tz
  bool imu = true;           // <imu>_gx ... <imu>_qz
};

// the names the columns are made of, in the segment's order
struct LogNames {
  std::vector<std::string> joints;  // q_<joint>, qref_<joint>, tau_<joint>
  std::vector<std::string> forces;  // <ft>_fx ...
  std::vector<std::string> imus;    // <imu>_gx ...
};
LogNames LogNamesOf(const RobotMap& robot);

class Recorder {
 public:
  // Opens `path` for writing and writes the header line. Returns null with `*error` set when
  // the file cannot be created. `capacity` rows are buffered in memory.
  static std::unique_ptr<Recorder> Open(const std::string& path, const LogNames& names,
                                        std::string* error, size_t capacity = 8192,
                                        const RecorderChannels& channels = {});
  static std::unique_ptr<Recorder> Open(const std::string& path, const RobotMap& robot,
                                        std::string* error, size_t capacity = 8192,
                                        const RecorderChannels& channels = {}) {
    return Open(path, LogNamesOf(robot), error, capacity, channels);
  }
  ~Recorder();  // flushes everything and closes the file

  // Queues one row (copies the values; no allocation). Returns false and counts a drop when
  // the ring is full (the writer fell behind).
  bool Push(const shm::SensorBlock& s, const shm::JointCommand* refs);

  // Writes out everything queued so far and flushes the file (not real-time safe).
  void Flush();
  uint64_t dropped() const { return dropped_.load(); }
  uint64_t written() const { return written_; }

 private:
  Recorder() = default;
  void WriterLoop();
  void WriteRow(const double* row);

  FILE* file_ = nullptr;
  size_t width_ = 0;     // doubles per row
  size_t capacity_ = 0;  // rows
  std::vector<double> ring_;
  std::atomic<uint64_t> head_{0};  // rows pushed
  std::atomic<uint64_t> tail_{0};  // rows written
  std::atomic<uint64_t> dropped_{0};
  uint64_t written_ = 0;
  int njoint_ = 0, nforce_ = 0, nimu_ = 0;  // 0 when the channel is off
  bool base_ = true;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread writer_;
  std::string line_;
};

}  // namespace ohrp::model
