// The sim_host process tests' fixture: the real sim_host binary started on the two-joint arm
// (test_models.h) with its stderr in a file, waits for its segment and its end, a controller
// attached from the test and one that dies in a forked child. Used by host_process_test.cc,
// host_faults_test.cc and host_pushes_test.cc.
#pragma once

#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/process.h"
#include "shm_bridge/bridge.h"
#include "test_models.h"

namespace ohrp::sim::testing {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

inline double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

class SimHostProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    segment_ = "simtest_" + std::to_string(getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name();
    fs::remove("/dev/shm/" + shm::SegmentObjectName(segment_));
    scene_ = testing::WriteTemp(testing::kTwoJointArm);
    err_ = testing::WriteTemp("", ".stderr");
  }
  void TearDown() override {
    ohrp::testing::Kill(&pid_);
    fs::remove("/dev/shm/" + shm::SegmentObjectName(segment_));
  }

  // starts sim_host on the arm model with `extra` options; stderr goes to err_
  void Start(std::vector<std::string> extra) {
    std::vector<std::string> args = {std::string(OHRP_BIN_DIR) + "/sim_host", "--scene", scene_,
                                     "--segment", segment_, "--physics-dt", "0.001",
                                     "--control-period", "0.002", "--progress", progress_};
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = ohrp::testing::Spawn(args, {.err = err_});
  }
  bool WaitSegment(double timeout = 5) {
    const auto t0 = Clock::now();
    while (Since(t0) < timeout) {
      if (fs::exists("/dev/shm/" + shm::SegmentObjectName(segment_))) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }
  // waits for sim_host to end; returns its exit code, or -1 on timeout (left running)
  int Wait(double timeout = 10) { return ohrp::testing::WaitExit(&pid_, timeout); }
  std::string Stderr() {
    std::ifstream in(err_);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  void Attach(shm::RobotAdaptor* a) {
    ASSERT_TRUE(WaitSegment());
    shm::Status st;
    for (int i = 0; i < 200; ++i) {
      st = a->open(segment_);
      if (st.ok()) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    FAIL() << st.message;
  }
  // in a forked controller: attaches `a` (retrying for up to a second) and answers 10 cycles
  // holding the pose read into `s`; a read that fails ends the child with exit code 2
  void AnswerTenCycles(shm::RobotAdaptor* a, shm::SensorBlock* s) {
    for (int i = 0; i < 200 && !a->open(segment_).ok(); ++i) usleep(5000);
    for (int k = 0; k < 10; ++k) {
      if (a->read(s) != shm::ReadResult::kOk) _exit(2);
      a->write(Hold(*s, 2));
    }
  }
  // a controller in another process that answers 10 cycles and dies without closing (its
  // claim stays on the segment: _exit); returns its exit code once it is reaped
  int RunDyingController() {
    const pid_t child = ohrp::testing::Spawn([&]() -> int {
      shm::RobotAdaptor a;
      shm::SensorBlock s{};
      AnswerTenCycles(&a, &s);
      _exit(0);
    });
    return ohrp::testing::WaitExit(child, ohrp::testing::kNoTimeout);
  }
  static shm::CommandBlock Hold(const shm::SensorBlock& s, int n) {
    shm::CommandBlock c{};
    c.njoint = n;
    for (int i = 0; i < n; ++i) {
      c.joint[i].mode = shm::JointMode::kPosition;
      c.joint[i].q_ref = s.q[i];
      c.joint[i].kp = 100;
      c.joint[i].kd = 10;
    }
    return c;
  }

  std::string segment_, scene_, err_;
  std::string progress_ = "0";  // --progress [s]
  pid_t pid_ = -1;
};

}  // namespace ohrp::sim::testing
