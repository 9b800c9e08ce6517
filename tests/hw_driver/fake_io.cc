// A RobotIo plugin for the hw_driver tests: an ideal robot whose joints go wherever the last
// position reference sends them while the servos are on, with faults injected at chosen reads,
// and a record of everything the driver wrote.
//
// Arguments (--io-arg KEY=VALUE):
//   q0=X            initial joint positions [rad] (default 0.1)
//   silent_at=N     from read N on (0-based) every board is silent
//   estop_at=N      from read N on the emergency-stop input is pressed
//   reset_at=N      from read N on a board reports a reset and its servos are off, until a
//                   write turns every servo off (the re-arm of udp/PROTOCOL.md)
//   nan_at=N        from read N on joint 0's position is NaN (board 0, io_fault::kNonFinite)
//   huge_at=N       from read N on joint 1's position reads 1e300 (a finite, implausible value)
//   servo_off_at=N  from read N on the boards report joint 1's servo off, whatever is written
//   offset_at=N     from read N on joint 0 reads 0.3 rad away from where it was sent
//   tilt_at=N       from read N on the IMU reads a tilt of 60 deg about x
//   reports=0       the plugin reports neither servo states nor follows commands (as replay)
//   refuse_at=N     from read N on the boards (one board, 0, carrying every joint) report that
//                   they refused the driver's last command, whatever it was
//   end_at=N        from read N on: end of data
//   fail_open=1     open fails ("fake: told to fail")
//   record=PATH     at close, one line per write: "<write> <reads> <servo> {<mode> <q_ref> <kp>
//                   <kd>} per joint", servo = 1 all on, 0 all off, 2 mixed
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "hw_driver/robot_io.h"

namespace {

using namespace ohrp::hw;

constexpr long kNever = -1;
constexpr size_t kMaxRecords = 200000;

struct Record {
  uint64_t reads;
  int servo;
  ohrp::shm::JointCommand joint[4];
};

class FakeIo final : public RobotIo {
 public:
  bool open(const IoConfig& config, std::string* error) override {
    double q0 = 0.1;
    for (const std::string& arg : config.args) {
      const auto eq = arg.find('=');
      const std::string key = arg.substr(0, eq);
      const std::string value = eq == std::string::npos ? "" : arg.substr(eq + 1);
      if (key == "q0") q0 = std::atof(value.c_str());
      else if (key == "silent_at") silent_at_ = std::atol(value.c_str());
      else if (key == "estop_at") estop_at_ = std::atol(value.c_str());
      else if (key == "reset_at") reset_at_ = std::atol(value.c_str());
      else if (key == "nan_at") nan_at_ = std::atol(value.c_str());
      else if (key == "huge_at") huge_at_ = std::atol(value.c_str());
      else if (key == "servo_off_at") servo_off_at_ = std::atol(value.c_str());
      else if (key == "offset_at") offset_at_ = std::atol(value.c_str());
      else if (key == "tilt_at") tilt_at_ = std::atol(value.c_str());
      else if (key == "reports") reports_ = value != "0";
      else if (key == "refuse_at") refuse_at_ = std::atol(value.c_str());
      else if (key == "end_at") end_at_ = std::atol(value.c_str());
      else if (key == "record") record_path_ = value;
      else if (key == "fail_open" && value == "1") {
        *error = "fake: told to fail";
        return false;
      } else {
        *error = "fake: unknown argument '" + arg + "'";
        return false;
      }
    }
    njoint_ = static_cast<int>(config.joint_names.size());
    for (int j = 0; j < njoint_; ++j) q_[j] = q0;
    records_.reserve(kMaxRecords);
    return true;
  }

  IoResult read(IoState* s) noexcept override {
    const long r = static_cast<long>(reads_++);
    s->faults = 0;
    s->silent_boards = 0;
    s->nonfinite_boards = 0;
    if (silent_at_ != kNever && r >= silent_at_) {
      s->faults |= io_fault::kBoardSilent;
      s->silent_boards = 1;
    }
    if (estop_at_ != kNever && r >= estop_at_) s->faults |= io_fault::kEmergencyStop;
    if (reset_at_ != kNever && r == reset_at_) {
      reset_ = true;
      servo_ = false;
    }
    if (reset_) s->faults |= io_fault::kBoardReset;
    if (end_at_ != kNever && r >= end_at_) s->faults |= io_fault::kEndOfData;
    s->time_ns = reads_ * 1000000;
    for (int j = 0; j < njoint_; ++j) {
      s->q[j] = q_[j];
      s->dq[j] = 0;
      s->tau[j] = 0;
      s->servo_on[j] = servo_;
    }
    s->reports = reports_ ? io_report::kServoState | io_report::kFollowsCommands : 0u;
    if (servo_off_at_ != kNever && r >= servo_off_at_ && njoint_ > 1) s->servo_on[1] = false;
    s->refused_boards = 0;
    if (refuse_at_ != kNever) {  // one board says which joints it carries and what it refused
      s->reports |= io_report::kBoards;
      for (int j = 0; j < njoint_; ++j) s->joint_board[j] = 0;
      if (r >= refuse_at_) s->refused_boards = 1;
    }
    if (offset_at_ != kNever && r >= offset_at_) s->q[0] += 0.3;
    if (huge_at_ != kNever && r >= huge_at_ && njoint_ > 1) s->q[1] = 1e300;
    s->imu[0].quat_WI[1] = 0;
    if (tilt_at_ != kNever && r >= tilt_at_) {  // 60 deg about x
      s->imu[0].quat_WI[0] = std::cos(M_PI / 6);
      s->imu[0].quat_WI[1] = std::sin(M_PI / 6);
    } else {
      s->imu[0].quat_WI[0] = 1.0;
    }
    if (nan_at_ != kNever && r >= nan_at_ && njoint_ > 0) {
      s->q[0] = std::nan("");
      s->faults |= io_fault::kNonFinite;
      s->nonfinite_boards = 1;
    }
    return s->faults ? IoResult::kFault : IoResult::kOk;
  }

  IoResult write(const IoCommand& c) noexcept override {
    int on = 0;
    for (int j = 0; j < njoint_; ++j) on += c.servo_on[j] ? 1 : 0;
    if (reset_ && on == 0) reset_ = false;  // re-armed
    servo_ = on == njoint_ && !reset_;
    for (int j = 0; j < njoint_; ++j) {
      if (servo_ && c.joint[j].mode == ohrp::shm::JointMode::kPosition) {
        q_[j] = c.joint[j].q_ref;
      }
    }
    if (records_.size() < kMaxRecords) {
      Record rec{reads_, on == njoint_ ? 1 : on == 0 ? 0 : 2, {}};
      for (int j = 0; j < njoint_ && j < 4; ++j) rec.joint[j] = c.joint[j];
      records_.push_back(rec);
    }
    return IoResult::kOk;
  }

  void close() noexcept override {
    if (record_path_.empty()) return;
    FILE* f = std::fopen(record_path_.c_str(), "w");
    if (f == nullptr) return;
    for (size_t i = 0; i < records_.size(); ++i) {
      const Record& r = records_[i];
      std::fprintf(f, "%zu %lu %d", i, static_cast<unsigned long>(r.reads), r.servo);
      for (int j = 0; j < njoint_ && j < 4; ++j) {
        std::fprintf(f, " %d %.17g %.17g %.17g", static_cast<int>(r.joint[j].mode),
                     r.joint[j].q_ref, r.joint[j].kp, r.joint[j].kd);
      }
      std::fprintf(f, "\n");
    }
    std::fclose(f);
  }

 private:
  int njoint_ = 0;
  double q_[ohrp::shm::kMaxJoints] = {};
  bool servo_ = false;
  bool reset_ = false;  // a board reset, not re-armed yet: its servos stay off
  uint64_t reads_ = 0;
  long silent_at_ = kNever, estop_at_ = kNever, reset_at_ = kNever, end_at_ = kNever,
       nan_at_ = kNever, huge_at_ = kNever, servo_off_at_ = kNever, offset_at_ = kNever,
       tilt_at_ = kNever, refuse_at_ = kNever;
  bool reports_ = true;
  std::string record_path_;
  std::vector<Record> records_;
};

}  // namespace

extern "C" ohrp::hw::RobotIo* ohrp_create_robot_io(uint32_t abi_version) {
  if (abi_version != ohrp::hw::kRobotIoAbiVersion) return nullptr;
  return new FakeIo();
}
