// The hw_driver process tests' fixture: the smallest robot the driver serves (kModel), the
// real hw_driver binary started on it with the fake boards (fake_io.cc, which records what the
// driver wrote), a read-only view of its segment, controllers in forked children, and waits that
// count cycles or poll conditions rather than sleep. Used by driver_process_test.cc and
// driver_recovery_test.cc.
#pragma once

#include <signal.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <boost/interprocess/mapped_region.hpp>
#include <boost/interprocess/shared_memory_object.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>
#include <vector>

#include "common/process.h"
#include "common/scratch.h"
#include "robot_model/model.h"
#include "robot_model/model_hash.h"
#include "shm_bridge/bridge.h"

namespace ohrp::hw::testing {

namespace fs = std::filesystem;
namespace bip = boost::interprocess;
using Clock = std::chrono::steady_clock;

// two hinges with limits, a F/T sensor and an IMU: the smallest robot the driver serves
constexpr const char* kModel = R"(
<mujoco model="hwbot">
  <compiler angle="radian"/>
  <worldbody>
    <body name="l1">
      <joint name="j1" type="hinge" axis="0 0 1" armature="1" limited="true" range="-1.5 1.5"/>
      <geom type="sphere" size="0.05" mass="1"/>
      <body name="l2" pos="0.1 0 0">
        <joint name="j2" type="hinge" axis="0 1 0" armature="1" limited="true" range="-1 1"/>
        <geom type="sphere" size="0.05" mass="1"/>
        <site name="ft"/>
        <site name="imu"/>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="j1" joint="j1" ctrllimited="true" ctrlrange="-50 50"/>
    <motor name="j2" joint="j2" ctrllimited="true" ctrlrange="-20 20"/>
  </actuator>
  <sensor>
    <force site="ft"/>
    <torque site="ft"/>
    <gyro site="imu"/>
    <accelerometer site="imu"/>
  </sensor>
</mujoco>
)";

inline double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// one line of fake_io's record: what the driver wrote once
struct Written {
  uint64_t reads = 0;  // reads done before this write
  int servo = 0;       // 1 all on, 0 all off, 2 mixed
  int mode[2] = {};
  double q_ref[2] = {}, kp[2] = {}, kd[2] = {};
};

// read-only view of a segment, kept mapped after the driver removes it
class Peek {
 public:
  explicit Peek(const std::string& segment)
      : shm_(bip::open_only, shm::SegmentObjectName(segment).c_str(), bip::read_only),
        region_(shm_, bip::read_only) {}
  const shm::Segment& get() const { return *static_cast<const shm::Segment*>(region_.get_address()); }
  uint64_t cycle() const {
    return std::atomic_ref<const uint64_t>(get().sensors.cycle).load(std::memory_order_relaxed);
  }
  uint32_t status() const {
    return std::atomic_ref<const uint32_t>(get().sensors.status).load(std::memory_order_relaxed);
  }

 private:
  bip::shared_memory_object shm_;
  bip::mapped_region region_;
};

class HwDriverProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    segment_ = "hwtest_" + std::to_string(getpid()) + "_" + name;
    fs::remove(ShmPath());
    dir_ = ohrp::testing::ScratchFolder(name);
    model_ = Write("model.xml", kModel);
  }
  void TearDown() override {
    for (pid_t* p : {&pid_, &child_}) ohrp::testing::Kill(p);
    fs::remove(ShmPath());
    if (!other_segment_.empty()) fs::remove("/dev/shm/" + shm::SegmentObjectName(other_segment_));
    fs::remove_all(dir_);
  }

  std::string ShmPath() const { return "/dev/shm/" + shm::SegmentObjectName(segment_); }
  std::string Path(const std::string& file) const { return (dir_ / file).string(); }
  std::string Write(const std::string& file, const std::string& text) {
    std::ofstream(Path(file)) << text;
    return Path(file);
  }

  // starts hw_driver on the test model with the fake boards (recording) unless `extra` names
  // another --io; stderr goes to a file
  void Start(std::vector<std::string> extra, const std::string& io = FAKE_IO_PATH) {
    std::vector<std::string> args = {std::string(OHRP_BIN_DIR) + "/hw_driver", "--model", model_,
                                     "--segment", segment_, "--io", io,
                                     "--summary", Path("summary.json")};
    if (io == FAKE_IO_PATH) {
      args.push_back("--io-arg");
      args.push_back("record=" + Path("record.txt"));
    }
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = Exec(args, Path("driver.stderr"));
  }
  // starts `args`, its stdout and stderr into the file `err`
  static pid_t Exec(const std::vector<std::string>& args, const std::string& err) {
    return ohrp::testing::Spawn(args, ohrp::testing::ToFile(err));
  }
  // waits until the driver's segment exists, has its full size and says kRunning
  bool WaitSegment(double timeout = 20) { return WaitRunning(segment_, timeout); }
  // the same for any producer's segment `segment`
  static bool WaitRunning(const std::string& segment, double timeout = 20) {
    const std::string path = "/dev/shm/" + shm::SegmentObjectName(segment);
    const auto t0 = Clock::now();
    while (Since(t0) < timeout) {
      std::error_code ec;
      if (fs::file_size(path, ec) == sizeof(shm::Segment) && !ec) {
        try {
          Peek peek(segment);
          const uint32_t state = std::atomic_ref<const uint32_t>(peek.get().header.state).load();
          if (state == static_cast<uint32_t>(shm::ProducerState::kRunning)) return true;
        } catch (const bip::interprocess_exception&) {
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  }
  // waits for process `*pid` to end; its exit code (128 + signal), or -1 on timeout (left running)
  static int WaitExit(pid_t* pid, double timeout = 30) {
    return ohrp::testing::WaitExit(pid, timeout);
  }
  int Wait(double timeout = 30) { return WaitExit(&pid_, timeout); }
  // polls `condition` every 2 ms until it holds (true) or `timeout` [s] passes (false)
  static bool WaitUntil(const std::function<bool()>& condition, double timeout = 30) {
    const auto t0 = Clock::now();
    while (!condition()) {
      if (Since(t0) > timeout) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
  }
  std::string Read(const std::string& file) {
    std::ifstream in(Path(file));
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  std::string Stderr() { return Read("driver.stderr"); }
  nlohmann::json Summary() { return nlohmann::json::parse(Read("summary.json")); }
  std::vector<Written> Records() {
    std::vector<Written> out;
    std::ifstream in(Path("record.txt"));
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream ss(line);
      Written w;
      size_t index = 0;
      ss >> index >> w.reads >> w.servo;
      for (int j = 0; j < 2; ++j) ss >> w.mode[j] >> w.q_ref[j] >> w.kp[j] >> w.kd[j];
      out.push_back(w);
    }
    return out;
  }
  // the cycle of the first event named `name` in the summary, or -1
  static long EventCycle(const nlohmann::json& summary, const std::string& name) {
    for (const auto& e : summary["events"]) {
      if (e["event"] == name) return e["cycle"].get<long>();
    }
    return -1;
  }
  // a controller in a forked child: attaches, then answers every cycle with `command` until the
  // producer stops (exit 0) or the attach fails (exit 2); after `signal_after` answers it sends
  // one byte through `answered` (when not null). Exit 0 also needs `need_status` seen in some
  // block. It ends with _exit: its adaptor is never closed.
  pid_t Controller(shm::CommandBlock command, int signal_after = -1,
                   ohrp::testing::Pipe* answered = nullptr, uint32_t need_status = 0) {
    const std::string segment = segment_;
    return ohrp::testing::Spawn([&]() -> int {
      shm::RobotAdaptor a;
      shm::Status st;
      for (int i = 0; i < 2000; ++i) {
        st = a.open(segment);
        if (st.ok()) break;
        usleep(5000);
      }
      if (!st.ok()) _exit(2);
      shm::SensorBlock s{};
      uint32_t seen = 0;
      for (int n = 0;; ++n) {
        const shm::ReadResult r = a.read(&s);
        if (r == shm::ReadResult::kProducerStopped) break;
        if (r != shm::ReadResult::kOk) _exit(3);
        seen |= s.status;
        a.write(command);
        if (n + 1 == signal_after && answered != nullptr && !answered->Send()) _exit(4);
      }
      _exit((seen & need_status) == need_status ? 0 : 5);
    });
  }
  static shm::CommandBlock Hold(double q1, double q2) {
    shm::CommandBlock c{};
    c.njoint = 2;
    const double q[2] = {q1, q2};
    for (int i = 0; i < 2; ++i) {
      c.joint[i].mode = shm::JointMode::kPosition;
      c.joint[i].q_ref = q[i];
      c.joint[i].kp = 10;
      c.joint[i].kd = 1;
    }
    return c;
  }

  std::string segment_, model_;
  std::string other_segment_;  // a second producer's segment, removed in TearDown
  fs::path dir_;
  pid_t pid_ = -1, child_ = -1;
};


}  // namespace ohrp::hw::testing
