// Test helpers: the fake robot and process spawning.
#include "fake_robot.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/scratch.h"

namespace ohrp::controllers::testing {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

std::vector<std::string> SampleRobotJoints() {
  return {"RLEG_HIP_R",      "RLEG_HIP_P",      "RLEG_HIP_Y",      "RLEG_KNEE",
          "RLEG_ANKLE_P",    "RLEG_ANKLE_R",    "RARM_SHOULDER_P", "RARM_SHOULDER_R",
          "RARM_SHOULDER_Y", "RARM_ELBOW",      "RARM_WRIST_Y",    "RARM_WRIST_P",
          "RARM_WRIST_R",    "LLEG_HIP_R",      "LLEG_HIP_P",      "LLEG_HIP_Y",
          "LLEG_KNEE",       "LLEG_ANKLE_P",    "LLEG_ANKLE_R",    "LARM_SHOULDER_P",
          "LARM_SHOULDER_R", "LARM_SHOULDER_Y", "LARM_ELBOW",      "LARM_WRIST_Y",
          "LARM_WRIST_P",    "LARM_WRIST_R",    "WAIST_P",         "WAIST_R",
          "CHEST"};
}

//---------------- fake robot ----------------

std::unique_ptr<FakeRobot> FakeRobot::Create(const FakeRobotSpec& spec, std::string* error) {
  shm::ProducerConfig config;
  config.segment_name = spec.segment;
  config.kind = shm::ProducerKind::kSimulation;
  config.robot_name = spec.robot_name;
  config.joint_names = spec.joints;
  const std::size_t n = spec.joints.size();
  config.default_kp.assign(n, spec.default_kp);
  config.default_kd.assign(n, spec.default_kd);
  config.control_period = spec.control_period;
  config.physics_period = spec.control_period;
  shm::Status status;
  auto producer = shm::Producer::Create(config, &status);
  if (!producer) {
    *error = status.message;
    return nullptr;
  }
  std::unique_ptr<FakeRobot> robot(new FakeRobot());
  robot->spec_ = spec;
  robot->producer_ = std::move(producer);
  robot->q_ = spec.q_init.empty() ? std::vector<double>(n, 0.0) : spec.q_init;
  return robot;
}

FakeRobot::~FakeRobot() = default;

shm::WaitResult FakeRobot::Cycle(double wait) {
  const double time = static_cast<double>(cycle_) * spec_.control_period;
  shm::SensorBlock& s = producer_->BeginSensors();
  s.cycle = cycle_;
  s.time = time;
  s.status = shm::status::kRunning | shm::status::kSimulated;
  for (std::size_t j = 0; j < q_.size(); ++j) {
    s.q[j] = q_[j];
    s.dq[j] = 0.0;
    s.tau[j] = 0.0;
  }
  producer_->PublishSensors();
  shm::CommandBlock commands{};
  shm::WaitResult r = producer_->WaitCommands(wait, &commands, 0.01);
  if (r == shm::WaitResult::kCommands) {
    CommandRecord rec;
    rec.cycle = commands.answers_cycle;
    rec.time = static_cast<double>(commands.answers_cycle) * spec_.control_period;
    for (std::size_t j = 0; j < q_.size(); ++j) {
      const shm::JointCommand& c = commands.joint[j];
      rec.mode.push_back(c.mode);
      rec.q_ref.push_back(c.q_ref);
      rec.dq_ref.push_back(c.dq_ref);
      rec.kp.push_back(c.kp);
      rec.kd.push_back(c.kd);
      q_[j] = c.q_ref;  // perfect tracking
    }
    records_.push_back(std::move(rec));
  } else if (r == shm::WaitResult::kNoController) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ++cycle_;
  return r;
}

bool FakeRobot::RunUntilCommands(std::size_t n, double wall_timeout) {
  const std::size_t goal = records_.size() + n;
  const auto t0 = Clock::now();
  while (records_.size() < goal) {
    if (Since(t0) > wall_timeout) return false;
    Cycle();
  }
  return true;
}

int FakeRobot::RunUntilExit(pid_t pid, double wall_timeout) {
  const auto t0 = Clock::now();
  while (Since(t0) < wall_timeout) {
    const int code = ohrp::testing::WaitExit(&pid, 0);  // one look
    if (code != -1) return code;
    Cycle(0.05);
  }
  ohrp::testing::Kill(pid);
  return -1;
}

void FakeRobot::Stop() { producer_.reset(); }

//---------------- files, segments, processes ----------------

double FindStartTime(const std::vector<CommandRecord>& records, double period,
                     double (*model)(double t0, const CommandRecord& r, const void* ctx),
                     const void* ctx) {
  double best_t0 = records.front().time;
  double best_error = 1e300;
  for (int k = 0; k < 5; ++k) {
    const double t0 = records.front().time - k * period;
    double error = 0.0;
    for (const CommandRecord& r : records) error = std::max(error, std::abs(model(t0, r, ctx)));
    if (error < best_error) {
      best_error = error;
      best_t0 = t0;
    }
  }
  return best_t0;
}

std::string ExternalDir() {
  const char* env = std::getenv("OHRP_EXTERNAL_DIR");
  std::string dir = env != nullptr ? env : std::string(OHRP_SOURCE_DIR) + "/../shared/external";
  return access(dir.c_str(), R_OK) == 0 ? dir : std::string();
}

std::string UniqueSegment(const std::string& tag) {
  return "ctltest_" + tag + "_" + std::to_string(getpid());
}

void RemoveSegment(const std::string& segment) {
  std::string path = "/";
  path += shm::SegmentObjectName(segment);
  shm_unlink(path.c_str());
}

std::string Program(const std::string& name) { return std::string(OHRP_BIN_DIR) + "/" + name; }

std::string TempPath(const std::string& tag) { return ohrp::testing::ScratchFile(tag, ""); }

void WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

pid_t Spawn(const std::vector<std::string>& args, const std::string& log_path) {
  return ohrp::testing::Spawn(args, ohrp::testing::ToFile(log_path, /*append=*/true));
}

}  // namespace ohrp::controllers::testing
