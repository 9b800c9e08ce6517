// Test helpers for cross-process controller tests: a fake robot (an ohrp::shm::Producer that
// runs lock-step and tracks the commands perfectly) and spawning the built programs (through
// common/process.h).
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "common/process.h"
#include "common/scratch.h"
#include "shm_bridge/bridge.h"

namespace ohrp::controllers::testing {

// SampleRobot's 29 joints in joint-id order
std::vector<std::string> SampleRobotJoints();

struct FakeRobotSpec {
  std::string segment;
  std::string robot_name = "SampleRobot";
  std::vector<std::string> joints;
  std::vector<double> q_init;        // empty: zeros
  double control_period = 0.005;     // [s]
  double default_kp = 100.0;         // [N m/rad] every joint
  double default_kd = 2.0;           // [N m s/rad]
};

// one command block as the fake robot received it
struct CommandRecord {
  uint64_t cycle = 0;      // answers_cycle
  double time = 0.0;       // producer time of that cycle [s]
  std::vector<shm::JointMode> mode;
  std::vector<double> q_ref, dq_ref, kp, kd;
};

class FakeRobot {
 public:
  // Creates the segment; null with `*error` set on failure.
  static std::unique_ptr<FakeRobot> Create(const FakeRobotSpec& spec, std::string* error);
  ~FakeRobot();

  // One control cycle: publish sensors (time = cycle * period, q = the last q_ref received),
  // wait up to `wait` [s] for commands, record them. When no controller is attached it
  // sleeps 1 ms so that an attaching controller finds a cycling producer.
  shm::WaitResult Cycle(double wait = 2.0);
  // Cycles until `n` more command blocks arrived or `wall_timeout` [s] passed.
  bool RunUntilCommands(std::size_t n, double wall_timeout = 20.0);
  // Cycles until process `pid` exits; returns its exit code, or -1 on timeout (then killed).
  int RunUntilExit(pid_t pid, double wall_timeout = 20.0);
  // Ends the run normally (state kStopped, segment removed).
  void Stop();
  // Lets the attached controller go as a producer does with one that missed its timeout
  // (shm::Producer::DropController); true when `pid` held the slot.
  bool DropController(pid_t pid) { return producer_->DropController(pid); }

  const std::vector<CommandRecord>& records() const { return records_; }
  pid_t controller_pid() const { return producer_->controller_pid(); }
  double period() const { return spec_.control_period; }

 private:
  FakeRobotSpec spec_;
  std::unique_ptr<shm::Producer> producer_;
  std::vector<double> q_;
  uint64_t cycle_ = 0;
  std::vector<CommandRecord> records_;
};

// OpenHRP / hrpsys reference data: $OHRP_EXTERNAL_DIR, else <source>/../shared/external
// ("" when neither exists; tests that need it skip with a message)
std::string ExternalDir();

// The producer time at which the controller read its first sensor block. Usually the time of
// the first record, but a block read just as the controller attached may have been answered
// too late to be recorded; so the candidates first.time - k * period (k = 0..4) are tried and
// the one for which `model(t0, record)` (the expected q_ref of one joint) fits best is returned.
double FindStartTime(const std::vector<CommandRecord>& records, double period,
                     double (*model)(double t0, const CommandRecord& r, const void* ctx),
                     const void* ctx);

// a segment name unique to this process and tag
std::string UniqueSegment(const std::string& tag);
// removes a segment object left behind (e.g. by a killed producer)
void RemoveSegment(const std::string& segment);
// the path of a built program in OHRP_BIN_DIR
std::string Program(const std::string& name);
// a fresh file (created empty) in the test's scratch folder (common/scratch.h)
std::string TempPath(const std::string& tag);
// writes `text` to `path`
void WriteText(const std::string& path, const std::string& text);
using ohrp::testing::ReadFile;  // common/scratch.h

// starts `args` (a program and its arguments) with stdout and stderr appended to `log_path`;
// returns the pid
pid_t Spawn(const std::vector<std::string>& args, const std::string& log_path);
// waits for a child without cycling anything: its exit code, or -1 on timeout (then killed)
using ohrp::testing::WaitExit;

}  // namespace ohrp::controllers::testing
