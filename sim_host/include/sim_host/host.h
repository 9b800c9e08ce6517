// sim_host: the simulation producer. Loads a scene, creates the robot's segment, steps MuJoCo,
// runs the joint servos at the physics rate, publishes the sensors every control period and
// takes the controller's commands, in lock-step (default) or paced to the wall clock.
//
// Time (see docs/architecture.md): the sensors of cycle k are those at the end of the physics
// steps of cycle k; the commands answering cycle k act from the next physics step on.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot_model/joint_params.h"
#include "robot_model/sensor_params.h"
#include "robot_model/output_file.h"

#include "shm_bridge/controller_loss.h"
#include "sim_host/cameras.h"
#include "sim_host/effects.h"
#include "sim_host/fall.h"
#include "sim_host/feet.h"
#include "sim_host/exit_codes.h"
#include "sim_host/pushes.h"

namespace ohrp::sim {

// What the run does when the controller dies, hangs past --controller-timeout or detaches
// (the policy both producers share, shm_bridge/controller_loss.h): kEnd stops the run (exit code
// kExitControllerLost), kWait holds the robot, freezes time and waits for a new controller,
// kContinue keeps simulating with the last references held. A controller that hung is dropped
// (its slot freed): it exits with the controllers' "dropped" code should it run again.
using ControllerLoss = shm::ControllerLoss;

struct HostOptions {
  std::string scene;               // MJCF file
  std::string segment = "hrp1s";   // segment name
  std::string keyframe;            // initial state; empty: the model's qpos0
  double physics_dt = 0;           // [s]; 0: the scene's timestep
  double control_period = 0;       // [s]; a multiple of the physics step; 0: the multiple
                                   // nearest 5 ms (sim_host/period.h)
  std::string integrator;          // euler | rk4 | implicit; empty: the scene's
  FeetOptions feet;                // the contact under the soles (default: soft-foot)
  std::string contact_file;        // where feet.params came from (--contact-file), or empty
  std::string joint_file;          // the joints as identified (--joint-file), or empty
  std::vector<model::JointParams> joints;  // its values, applied to the model at set-up
  std::string sensor_file;         // the sensors as identified (--sensor-file), or empty
  model::SensorParams sensors;     // its values (by name), applied to the sensors' readings
  uint64_t sensor_seed = 1;        // the seed of their noise (--sensor-seed)
  std::vector<Perturbation> pushes; // external pushes on the base (none by default)
  double duration = 0;             // simulated time to run [s]; 0: until Ctrl-C
  bool realtime = false;           // pace cycles to the wall clock
  double wait_controller = 30;     // [s] wall time to wait for the first controller; 0: run without
  double controller_timeout = 1.0; // [s] wall time a lock-step controller may take per cycle
  ControllerLoss on_loss = ControllerLoss::kEnd;
  std::string log_path;            // CSV data log; empty: none
  int log_every = 1;               // record one row every N control cycles
  bool log_dq = false;             // the log also records the joints' velocities (dq_<joint>)
  uint64_t log_max = 0;            // [bytes] the log's size bound (--log-max): rows past it are
                                   // not written, and counted; 0: none
  std::string summary_path;        // JSON summary at the end; empty: none
  double progress = 2.0;           // [s] wall time between progress lines; 0: none
  bool quiet = false;
  EffectRequests effects;          // effects switched on/off by request (sim_host/effects.h)
  bool explain = false;            // print the effects table and exit without running
  std::string self_collision_file; // the self_collision effect's pairs: a file of
                                   // ohrp_selfcollision (implies self_collision=on); empty: all
                                   // non-adjacent pairs (sim_host/self_collision_watch.h)
  CameraOptions cameras;           // the robot's cameras: size, rate (sim_host/cameras.h)
  std::string record_images;       // every camera's images written to this folder (--record-images,
                                   // image_recorder.h); empty: none
  std::string control_socket;      // the control channel's socket (sim_host/control_channel.h);
                                   // empty: none
  FallOptions fall;                // the fall watch: end or continue, bodies allowed to touch
                                   // the ground (sim_host/fall.h)
};

// Runs one simulation as described by `options`; returns an exit code above. Prints set-up
// errors and the end-of-run report on stderr.
int RunHost(const HostOptions& options);

}  // namespace ohrp::sim
