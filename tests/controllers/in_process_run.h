// Test helper: a built controller program against a robot simulated in this test's process
// (sim_host::InProcessRobot) through a segment of its own. The test may edit the commands the
// robot receives (e.g. make it limp) and the sensor blocks the program reads; the run ends at
// `t_end` of producer time, or as soon as the program leaves the segment (it ended its run
// itself: a fall, a failure).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "fake_robot.h"
#include "robot_model/sensors.h"
#include "shm_bridge/bridge.h"
#include "sim_host/in_process.h"

namespace ohrp::controllers::testing {

struct InProcessRun {
  std::vector<std::string> args;  // the program and its arguments, without --segment
  sim::InProcessOptions io;       // the robot (scene, keyframe, pushes)
  double t_end = 10.0;            // [s] producer time
  double wall = 120.0;            // [s] wall bound
  // edits the commands before the robot takes them (producer time, commands)
  std::function<void(double, shm::CommandBlock*)> edit_commands;
  // edits the sensor block the program reads (the simulation itself is untouched)
  std::function<void(shm::SensorBlock*)> edit_sensors;
  // edits the robot's initial state once it is created (e.g. a tilted start)
  std::function<void(sim::InProcessRobot*)> setup;
};

struct InProcessResult {
  int exit_code = -1;
  std::string output;       // the program's stdout and stderr
  double last_time = 0;     // producer time when the run ended [s]
  bool left_early = false;  // the program left before t_end
  double base_z = 0;        // truth at the end [m]
};

// A command block holding every joint where `robot` measures it now, on the header's gains.
inline shm::CommandBlock HoldWhereItIs(const sim::InProcessRobot& robot) {
  const int n = static_cast<int>(robot.header().njoint);
  shm::CommandBlock hold{};
  hold.njoint = n;
  for (int j = 0; j < n; ++j) {
    hold.joint[j].mode = shm::JointMode::kPosition;
    hold.joint[j].q_ref = robot.sensors().q[j];
    hold.joint[j].kp = robot.header().default_kp[j];
    hold.joint[j].kd = robot.header().default_kd[j];
  }
  return hold;
}

inline InProcessResult RunInProcess(const std::string& tag, const InProcessRun& spec) {
  InProcessResult out;
  std::string error;
  auto robot = sim::InProcessRobot::Create(spec.io, &error);
  EXPECT_TRUE(robot) << error;
  if (!robot) return out;
  if (spec.setup) spec.setup(robot.get());
  const std::string segment = UniqueSegment(tag);
  shm::Status status;
  auto producer = shm::Producer::Create(
      model::MakeProducerConfig(robot->robot(), robot->m(), segment, robot->m()->opt.timestep,
                                spec.io.control_period),
      &status);
  EXPECT_TRUE(producer) << status.message;
  if (!producer) return out;
  std::vector<std::string> args = spec.args;
  args.insert(args.begin() + 1, {"--segment", segment});
  const std::string log = TempPath(tag);
  const pid_t pid = Spawn(args, log);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  shm::CommandBlock cmd{};
  bool answered = false;
  while (robot->sensors().time < spec.t_end && wall() < spec.wall) {
    shm::SensorBlock& s = producer->BeginSensors();
    const uint64_t seq = s.seq;
    s = robot->sensors();
    s.seq = seq;
    if (spec.edit_sensors) spec.edit_sensors(&s);
    producer->PublishSensors();
    const shm::WaitResult r = producer->WaitCommands(2.0, &cmd, 0.01);
    if (r == shm::WaitResult::kCommands) {
      answered = true;
      if (spec.edit_commands) spec.edit_commands(robot->sensors().time, &cmd);
      robot->Cycle(cmd);
    } else if (r == shm::WaitResult::kNoController || r == shm::WaitResult::kControllerDied) {
      if (answered || !ohrp::testing::Running(pid)) {  // the program left: it ended its run
        out.left_early = true;
        break;
      }
      // time frozen until the program attaches, as sim_host does (a slow start on a loaded
      // machine must not eat the run's producer time)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    } else {
      ADD_FAILURE() << "the program did not answer: " << static_cast<int>(r);
      break;
    }
  }
  out.last_time = robot->sensors().time;
  out.base_z = robot->sensors().sim_truth.p_WB[2];
  producer.reset();  // ends the run: the program reports and exits
  out.exit_code = WaitExit(pid, spec.wall);
  out.output = ReadFile(log);
  std::filesystem::remove(log);
  return out;
}

// HRP-1S half-sitting on the flat floor, 5 ms control
inline sim::InProcessOptions Hrp1sStanding() {
  sim::InProcessOptions io;
  io.scene = std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/scene_flat.xml";
  io.keyframe = "halfsit";
  io.control_period = 0.005;
  return io;
}

}  // namespace ohrp::controllers::testing
