// A robot simulated in the caller's process, stepped as sim_host steps it (servo at every
// physics step, the contact under the soles, mj_step, pushes on the base), with the segment's
// header and sensor blocks but no handshake: for tests and benchmarks of controllers that need
// real sensor blocks without the processes around them.
//
//   InProcessRobot robot = *InProcessRobot::Create(options, &error);
//   controller.configure(robot.header());
//   controller.activate(robot.sensors());
//   while (...) { controller.update(robot.sensors(), &commands); robot.Cycle(commands); }
//
// The header is the one sim_host publishes (a real Producer builds it; the segment, named
// uniquely, is removed with the object). Cycle never allocates.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "shm_bridge/bridge.h"
#include "sim_host/feet.h"
#include "sim_host/host.h"
#include "sim_host/step.h"

namespace ohrp::sim {

struct InProcessOptions {
  std::string scene;               // MJCF file
  std::string keyframe;            // initial state; empty: the model's qpos0
  double physics_dt = 0.001;       // [s]; 0: the scene's
  double control_period = 0.005;   // [s], a multiple of the physics step
  FeetOptions feet;                // contact under the soles (default: soft when there are soles)
  std::vector<Perturbation> pushes;  // wrenches on the base over windows of simulated time
};

class InProcessRobot {
 public:
  // Loads the scene, sets the contact up, resets to the keyframe, holds the initial pose and
  // publishes the sensors of cycle 0. Null with `*error` set on failure.
  static std::unique_ptr<InProcessRobot> Create(const InProcessOptions& options,
                                                std::string* error);
  ~InProcessRobot();

  const shm::SegmentHeader& header() const { return producer_->header(); }
  // the sensors at the end of the current cycle (status kSimulated: sim_truth is valid)
  const shm::SensorBlock& sensors() const { return sensors_; }
  // Takes the commands answering the current cycle (the servo checks them as sim_host's does),
  // runs one control period of physics, and fills the sensors of the next cycle. Returns the
  // number of joint commands the servo rejected.
  int Cycle(const shm::CommandBlock& commands);

  mjModel* m() const { return scene_->m(); }
  mjData* d() const { return scene_->d(); }
  const model::RobotMap& robot() const { return robot_; }

 private:
  InProcessRobot() = default;
  void Publish();

  InProcessOptions options_;
  std::unique_ptr<model::Scene> scene_;
  model::RobotMap robot_;
  std::unique_ptr<contact::SoftFootContact> soft_;
  std::unique_ptr<model::Servo> servo_;
  std::unique_ptr<shm::Producer> producer_;
  shm::SensorBlock sensors_{};
  int steps_per_cycle_ = 1;
  std::unique_ptr<PhysicsStep> step_;  // the physics step, sim_host's (step.h)
  uint64_t cycle_ = 0;
};

}  // namespace ohrp::sim
