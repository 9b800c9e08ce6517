// One run of sim_host (RunHost, host.h) as an object: its set-up (host_setup.cc), the named
// stages of a control cycle (host_loop.cc) and the shutdown that reports the run. Internal to
// the sim_host library.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "shm_bridge/bridge.h"
#include "image_recorder.h"
#include "sim_host/cameras.h"
#include "sim_host/control_channel.h"
#include "sim_host/divergence.h"
#include "sim_host/effects.h"
#include "sim_host/fall.h"
#include "sim_host/feet.h"
#include "sim_host/guard_watch.h"
#include "sim_host/host.h"
#include "robot_model/model.h"
#include "robot_model/command_delay.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"
#include "datalog/recorder.h"
#include "sim_host/report.h"
#include "sim_host/self_collision_watch.h"
#include "sim_host/step.h"

namespace ohrp::sim {

class HostRun {
 public:
  // `signal`: set by the signal handler (non-zero ends the run); `segment_object`: where the
  // segment's object name is written once it exists (the fatal-error path removes it)
  HostRun(const HostOptions& options, const std::atomic<int>* signal, char* segment_object,
          size_t segment_object_size);
  ~HostRun();

  // scene, robot, effects, watches, log, segment; kExitOk when the loop may run, otherwise the
  // exit code (a refusal, with its message printed; --explain printed, then *ran_enough = true)
  int SetUp(bool* ran_enough);
  // the control cycles until the duration, a signal or an ending event; then the report
  int Run();

 private:
  enum class Next { kStep, kAgain, kEnd };  // what a cycle does after its commands

  //---- set-up (host_setup.cc)
  bool LoadScene(std::string* error);
  bool SetUpWatches(std::string* error);
  bool ApplyJointFile(std::string* error);
  bool SetUpSensorModel(std::string* error);
  void SetUpCommandDelay();
  bool OpenImages(std::string* error);
  void EndImages();
  bool OpenLog(std::string* error);
  bool CreateSegment(std::string* error);
  bool OpenControl(std::string* error);

  //---- the control channel's actions, between cycles (host_control.cc)
  bool ControlGate();
  void ApplyAction(const ControlAction& a);
  void EndControlPush();
  void ControlDone(int kind);

  //---- the stages of a cycle (host_loop.cc)
  void StartLoop();
  void Publish(uint32_t flags, bool record = true) noexcept;
  bool SegmentCorrupted();
  Next Commands();
  Next WaitForController();
  Next TakeCommands();
  void Accept();
  bool LoseController(const char* why, const char* event, pid_t pid);
  bool Physics();
  void RecordDivergence();
  bool Watches();
  void PaceAndPublish();
  void Progress();
  int Shutdown();

  HostOptions o;
  const HostOptions& given;  // the options as passed (the control period asked for)
  const std::atomic<int>* signal;
  char* segment_object;
  size_t segment_object_size;

  //---- set up once
  std::unique_ptr<model::Scene> scene;
  mjModel* m = nullptr;
  mjData* d = nullptr;
  model::RobotMap robot;
  std::unique_ptr<contact::SoftFootContact> soft;
  ContactModel contact_model{};
  EffectsPlan effects;
  bool filter_set = false;  // the scene's contact filter is set: cleared at the end
  std::unique_ptr<FallWatch> fall;
  double dt = 0;
  int steps_per_cycle = 1;
  uint64_t identity_hash = 0;  // the model file's hash, published whatever --joint-file changed
  std::unique_ptr<SelfCollisionWatch> self_collision;
  std::unique_ptr<datalog::Recorder> recorder;
  model::SensorSelection selection{};
  std::vector<int> delay_cycles;                // per joint, the joint file's delay: in cycles
  model::CommandDelay delay;                     // the servo applies the commands of then
  std::unique_ptr<model::SensorModel> sensors;  // --sensor-file's bias and noise, noise=on's noise
  std::vector<double> q_min, q_max;             // the joints' limits, for its encoder bias
  std::unique_ptr<shm::Producer> producer;
  std::unique_ptr<Cameras> cameras;
  std::unique_ptr<ImageRecorder> images;  // --record-images (image_recorder.h)
  std::unique_ptr<model::Servo> servo;
  std::unique_ptr<DivergenceWatch> watch;
  std::unique_ptr<PhysicsStep> stepper;

  //---- the loop's state
  RunStats st;
  double next_progress = 0;
  double wait_since = 0;
  bool had_controller = false;
  bool waiting = false;         // waiting for a (new) controller, time frozen
  uint32_t extra_status = 0;
  long warnings_at_start = 0;
  shm::CommandBlock cmd{};
  GuardWatch guard;             // the hold episodes of the controller's self-collision guard
  int exit_code = kExitOk;
  bool republish = false;       // the next controller reads the last cycle again, as holding
  pid_t last_controller = 0;    // the pid of the last controller that attached
  bool rejecting = false;       // its last command block had rejected joints
  double deadline = 0;          // real time: the wall time at which the cycle is due
  std::string error;

  //---- the control channel (--control-socket)
  std::unique_ptr<ControlChannel> control;
  bool paused = false;
  int steps_left = 0;           // paused: control periods still to run (step N)
  bool step_owed = false;       // a step's answer, owed once its periods have run
  double heartbeat = 0;         // paused: the wall time of the last republished block
  int push_body = -1;           // the channel's push under way: body, force, end time
  double push_force[3] = {0, 0, 0};
  double push_end = 0;
  int start_keyframe = -1;      // reset alone: the run's start (--keyframe; -1 qpos0)
  std::vector<double> saved_xfrc;  // reset: the bodies' wrenches kept (sized at set-up)
};

}  // namespace ohrp::sim
