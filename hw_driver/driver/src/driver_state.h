// The driver loop's state (Driver::Impl): what one cycle reads, publishes and writes, the
// event log, and the data log's hook. Internal to the driver library (driver.cc).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "hw_driver/board_checks.h"
#include "hw_driver/driver.h"
#include "hw_driver/guard.h"
#include "datalog/recorder.h"

namespace ohrp::hw {

inline constexpr size_t kMaxEvents = 1024;  // events kept per run; more are counted as dropped

// the servo period [ns] (at least 1 us)
inline int64_t PeriodNs(const DriverOptions& o) {
  return std::max<int64_t>(1000, std::llround(o.period * 1e9));
}

inline void Bump(std::atomic<uint64_t>& a, uint64_t n = 1) {
  a.store(a.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
}

inline bool AllFinite(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

// the plugin's camera images go into the segment
class SegmentImages final : public ImageSink {
 public:
  explicit SegmentImages(shm::Producer* p) : producer_(p) {}
  bool Publish(int camera, double time, int width, int height, const uint8_t* rgb,
               const float* depth) noexcept override {
    return producer_->PublishImage(camera, time, width, height, rgb, depth) ==
           shm::ImageResult::kOk;
  }

 private:
  shm::Producer* producer_;
};

// how often the loop looks at the segment's image requests (one kill(pid, 0) per requester)
inline constexpr uint64_t kImageRequestPollCycles = 10;

struct Driver::Impl {
  Impl(const DriverOptions& o, const shm::ProducerConfig& r, RobotIo* i, shm::Producer* p)
      : opt(o), robot(r), io(i), producer(p), guard(r),
        checks(r, o.board_timeout_cycles,
               static_cast<int>(std::ceil(o.tracking_time / std::max(o.period, 1e-6)))),
        waker(o.wake, PeriodNs(o)), images(p) {
    ncamera = static_cast<int>(r.cameras.size());
    njoint = static_cast<int>(r.joint_names.size());
    nforce = static_cast<int>(r.force_names.size());
    nimu = static_cast<int>(r.imu_names.size());
    npassive = static_cast<int>(r.passive_names.size());
    events.reserve(kMaxEvents);
  }

  const DriverOptions opt;
  const shm::ProducerConfig& robot;
  RobotIo* io;
  shm::Producer* producer;
  CommandGuard guard;
  BoardChecks checks;  // the boards' verification (board_checks.h)
  Waker waker;  // sleeps (and spins) to each cycle's start
  SegmentImages images;
  uint32_t images_wanted = 0;  // the cameras some program asks for (polled every few cycles)
  int njoint = 0, nforce = 0, nimu = 0, npassive = 0, ncamera = 0;

  IoState in{};
  double last_valid_q[shm::kMaxJoints] = {};  // positions of the last valid read
  IoCommand out{};
  // a board reset held through (driver.cc): its joints are re-armed (servo off), then ramped
  // from where they were measured back to their references while the others hold theirs
  bool joint_off[shm::kMaxJoints] = {};    // servo off for this joint although the robot's is on
  bool rearm_joint[shm::kMaxJoints] = {};  // on the reset board
  double ramp_from[shm::kMaxJoints] = {};
  shm::JointCommand ramp_to[shm::kMaxJoints] = {};
  bool commanded_on[shm::kMaxJoints] = {};  // what the last write asked of each servo
  double imu_reference[4] = {1, 0, 0, 0};   // the IMU's orientation at servo-on (the fall check)
  bool have_imu_reference = false;
  shm::CommandBlock cmd{};
  bool guard_holding = false;  // the controller's guard held the last accepted block
  std::vector<Event> events;
  uint64_t events_dropped = 0;

  DriverState state = DriverState::kInactive;
  bool servo_on = false;
  bool estopped = false;
  uint32_t late_flag = 0;      // kCommandLate until the next accepted block
  uint32_t rejected_flag = 0;  // kCommandRejected until the next accepted block
  uint64_t last_command_cycle = 0;
  uint64_t k = 0;
  double time = 0;             // driver time of cycle k [s]
  datalog::Recorder* log = nullptr;  // the data log (--log), or none
  uint64_t logged_board_ns = 0;      // log_board_time: the boards' time of the last row
  // log_board_time with io_report::kAppliedReferences: the references the boards had when they
  // measured the row's data (IoState::applied_q, applied_dq), the rest of each command the
  // driver's (a copy: no allocation)
  shm::JointCommand applied[shm::kMaxJoints] = {};

  void Record(EventKind kind, int64_t value = 0, int board = -1, int joint = -1,
              double reading = 0) noexcept {
    if (events.size() < kMaxEvents) {
      // capacity reserved: no allocation
      events.push_back(Event{k, time, kind, value, board, joint, reading});
    } else {
      ++events_dropped;
    }
  }

  // the controller's self-collision guard in the block just accepted: a hold's begin and end
  // are events (the held pair is in the controller's report and the data log's guard_holding)
  void NoteGuard() noexcept {
    const bool holding = cmd.guard.holding != 0;
    if (holding == guard_holding) return;
    guard_holding = holding;
    Record(holding ? EventKind::kGuardHoldBegin : EventKind::kGuardHoldEnd,
           static_cast<int64_t>(cmd.guard.holds), -1, -1, cmd.guard.distance);
  }

  void Publish(uint32_t flags, const LiveStats& live, bool record = true) noexcept {
    shm::SensorBlock& s = producer->BeginSensors();
    s.cycle = k;
    s.time = time;
    s.status = shm::status::kRunning | flags | late_flag | rejected_flag |
               (producer->controller_pid() ? 0u : shm::status::kNoController) |
               (state == DriverState::kSafeMode || state == DriverState::kStopping
                    ? shm::status::kHolding : 0u) |
               (servo_on ? 0u : shm::status::kServoOff) |
               (estopped ? shm::status::kEmergencyStop : 0u);
    s.last_command_cycle = last_command_cycle;
    s.late_commands = live.late_commands.load(std::memory_order_relaxed);
    s.rejected_commands = guard.rejected_total();
    std::memcpy(s.rejected_per_joint, guard.rejected_per_joint(), njoint * sizeof(uint32_t));
    std::memcpy(s.q, in.q, njoint * sizeof(double));
    std::memcpy(s.dq, in.dq, njoint * sizeof(double));
    std::memcpy(s.tau, in.tau, njoint * sizeof(double));
    std::memcpy(s.force, in.force, nforce * sizeof(shm::ForceTorque));
    std::memcpy(s.imu, in.imu, nimu * sizeof(shm::Imu));
    std::memcpy(s.passive_q, in.passive_q, npassive * sizeof(double));
    std::memcpy(s.passive_dq, in.passive_dq, npassive * sizeof(double));
    s.sim_truth = shm::SimTruth{};
    producer->PublishSensors();
    // the data log, as sim_host's: the block just published and the references the servos held
    // over the interval it ends (written in the previous cycle); a copy into the log's ring
    if (!record || !log || k % static_cast<uint64_t>(opt.log_every) != 0) return;
    if (!opt.log_board_time) {
      log->Push(s, guard.references(), cmd.guard.holding);  // the last accepted block's guard
    } else if (in.time_ns > logged_board_ns) {  // the boards' time: new data only (the gaps
      logged_board_ns = in.time_ns;              // in the log's time show the cycles left out)
      const shm::JointCommand* refs = guard.references();
      if (in.reports & io_report::kAppliedReferences) {  // what the boards had, not the driver
        std::memcpy(applied, refs, njoint * sizeof(shm::JointCommand));
        for (int i = 0; i < njoint; ++i) applied[i].q_ref = in.applied_q[i], applied[i].dq_ref = in.applied_dq[i];
        refs = applied;
      }
      log->Push(s, refs, cmd.guard.holding, static_cast<double>(in.time_ns) * 1e-9);
    }
  }

  void Write() noexcept {
    const shm::JointCommand* ref = guard.references();
    for (int i = 0; i < njoint; ++i) {
      out.servo_on[i] = servo_on && !joint_off[i];
      commanded_on[i] = out.servo_on[i];
      out.joint[i] = ref[i];
    }
    io->write(out);
  }
};

}  // namespace ohrp::hw
