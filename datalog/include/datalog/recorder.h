// The data log of a producer (sim_host --log, hw_driver --log): one CSV row per recorded control
// cycle, written by a background thread from a preallocated ring, so the simulation loop or the
// driver's servo cycle never formats, allocates or blocks on disk. Both producers write the same
// format with the same column names; datalog::Table (datalog/table.h) reads it back. The names
// come from the robot's map (robot_model/log_names.h: LogNamesOf) or are given.
//
// Columns (first line of the file; SI units, angles in rad):
//   time, base_x, base_y, base_z, base_qw, base_qx, base_qy, base_qz,   (simulation ground truth:
//   base_vx, base_vy, base_vz,                                           sim_host only)
//   q_<joint>... , qref_<joint>... , tau_<joint>...                      (joint-id order)
//   dq_<joint>...                        (only with RecorderChannels::joint_velocities)
//   dqref_<joint>...                     (only with RecorderChannels::reference_velocities)
//   q_<passive>... , dq_<passive>...                  (passive joints, read-only: header order)
//   <ft>_fx, <ft>_fy, <ft>_fz, <ft>_tx, <ft>_ty, <ft>_tz ...             (segment convention)
//   <imu>_gx, <imu>_gy, <imu>_gz, <imu>_ax, <imu>_ay, <imu>_az,
//   <imu>_qw, <imu>_qx, <imu>_qy, <imu>_qz ...
//   status, rejected, guard_holding
// The channels (base, joints with the passive ones, F/T, IMU) can be left out (RecorderChannels, the log_* effects of
// sim_host/effects.h); time, status and rejected are always there. hw_driver has no ground
// truth: its logs have no base_* columns (base = false), the sensor channels are the same.
// qref_ is the reference the servos held over the interval that ends at the row's time;
// guard_holding is 1 when the commands that acted over it were held by the controller's
// self-collision guard (shm::GuardRecord::holding), else 0.
#pragma once

#include <atomic>
#include <limits>
#include <cstdint>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::datalog {

// which column groups the log has
struct RecorderChannels {
  bool base = true;          // base_x ... base_vz
  bool joints = true;        // q_, qref_, tau_; the passive joints' q_, dq_
  bool force_torque = true;  // <ft>_fx ... <ft>_tz
  bool imu = true;           // <imu>_gx ... <imu>_qz
  // with joints: dq_<joint> after tau_ (sim_host/hw_driver --log-dq); last, so that the brace
  // initialisations {base, joints, force_torque, imu} keep their meaning
  bool joint_velocities = false;
  // with joints: dqref_<joint> after dq_, the reference velocity of the servos' commands
  // (hw_driver --log-dq: on the boards' time the one the boards applied)
  bool reference_velocities = false;
};

// the names the columns are made of, in the segment's order
struct LogNames {
  std::vector<std::string> joints;  // q_<joint>, qref_<joint>, tau_<joint>
  std::vector<std::string> forces;  // <ft>_fx ...
  std::vector<std::string> imus;    // <imu>_gx ...
  std::vector<std::string> passive; // q_<passive>, dq_<passive> (with the joints' channel)
};

// What reached the disk, and what did not (Recorder::Close, then the accessors below).
//   rows_on_disk   rows written whole by write(2) (and synced to the disk at Close): what the
//                  file holds, the only row count a report may give as "logged"
//   dropped        rows the ring could not take (the writer fell behind; Push returned false)
//   lost           rows taken but never written because a write failed (disk full, I/O error,
//                  file size limit): every row after the failure
//   over_limit     rows not written because the log reached its size bound (max_bytes)
// A write that fails part-way through a row leaves no half row: the file is cut back to the
// last whole row (ftruncate), and the log stops there (later rows are counted as lost).
class Recorder {
 public:
  // Opens `path` for writing (created or truncated) and writes the header line, checked: a path
  // that cannot be created or that takes no data (/proc/version, /dev/full) is refused here,
  // before the run, with `*error` naming the path and the reason. `capacity` rows are buffered
  // in memory. `max_bytes` > 0 bounds the file (header included): the first row that would pass
  // it, and every row after, is not written (counted in over_limit()); a bound too small for the
  // header and one row is refused.
  static std::unique_ptr<Recorder> Open(const std::string& path, const LogNames& names,
                                        std::string* error, size_t capacity = 8192,
                                        const RecorderChannels& channels = {},
                                        uint64_t max_bytes = 0);
  ~Recorder();  // Close()

  // Queues one row (copies the values; no allocation, no lock). Returns false and counts a drop
  // when the ring is full (the writer fell behind). `time` (not NaN) is the row's time instead
  // of s.time (hw_driver --log-time board: the boards' timestamp).
  bool Push(const shm::SensorBlock& s, const shm::JointCommand* refs, uint32_t guard_holding = 0,
            double time = std::numeric_limits<double>::quiet_NaN());

  // Writes out everything queued so far (not real-time safe).
  void Flush();
  // Ends the log: stops the writer thread, writes everything queued, syncs the file to the disk
  // (fdatasync) and closes it, each result checked. Returns !failed(). Idempotent.
  bool Close();

  // A write (or the final sync or close) failed: the log is incomplete. Safe to poll from the
  // real-time loop (one atomic load).
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  // The log reached max_bytes: later rows are not written (over_limit()).
  bool limit_reached() const { return limit_reached_.load(std::memory_order_acquire); }
  // Once failed(): "write failed after 161 rows (20007 bytes): No space left on device".
  std::string error() const;
  // The time and cycle (SensorBlock::time, ::cycle) of the first row the failure (or the limit)
  // kept off the disk; 0 when none.
  double failure_time() const { return failure_time_; }
  uint64_t failure_cycle() const { return failure_cycle_; }
  double limit_time() const { return limit_time_; }
  uint64_t limit_cycle() const { return limit_cycle_; }

  uint64_t rows_on_disk() const { return rows_on_disk_.load(); }
  uint64_t bytes_on_disk() const { return bytes_on_disk_.load(); }  // header included
  uint64_t dropped() const { return dropped_.load(); }
  uint64_t lost() const { return lost_.load(); }
  uint64_t over_limit() const { return over_limit_.load(); }
  uint64_t max_bytes() const { return max_bytes_; }
  const std::string& path() const { return path_; }

  // One sentence for a program's report: "data log run/log.csv: 2001 rows on disk (622 kB)",
  // then what did not reach it: the failure with its time and reason and the rows lost, the
  // size bound and the rows past it, the rows dropped by a full ring.
  std::string Describe() const;

 private:
  Recorder() = default;
  void WriterLoop();
  void AppendRow(const double* row);
  void WriteBatch();
  void Fail(int err, const char* what);

  std::string path_;
  int fd_ = -1;
  size_t width_ = 0;     // doubles per row
  size_t capacity_ = 0;  // rows
  uint64_t max_bytes_ = 0;
  std::vector<double> ring_;
  std::vector<uint64_t> cycles_;   // each slot's SensorBlock::cycle
  std::atomic<uint64_t> head_{0};  // rows pushed
  std::atomic<uint64_t> tail_{0};  // rows taken by the writer
  std::atomic<uint64_t> dropped_{0};
  std::atomic<uint64_t> rows_on_disk_{0};
  std::atomic<uint64_t> bytes_on_disk_{0};
  std::atomic<uint64_t> lost_{0};
  std::atomic<uint64_t> over_limit_{0};
  std::atomic<bool> failed_{false};
  std::atomic<bool> limit_reached_{false};
  double failure_time_ = 0, limit_time_ = 0;
  uint64_t failure_cycle_ = 0, limit_cycle_ = 0;
  std::string error_;  // set once, before failed_
  int njoint_ = 0, nforce_ = 0, nimu_ = 0, npassive_ = 0, ndq_ = 0, ndqref_ = 0;  // 0 when the channel is off
  bool base_ = true;
  bool closed_ = false;
  std::atomic<bool> stop_{false};
  mutable std::mutex mutex_;  // the writer's state: the batch and the file
  std::condition_variable wake_;
  std::thread writer_;
  // the writer's batch: formatted rows, where each ends, their times and cycles
  std::string batch_;
  std::vector<size_t> ends_;
  std::vector<double> times_;
  std::vector<uint64_t> batch_cycles_;
};

}  // namespace ohrp::datalog
