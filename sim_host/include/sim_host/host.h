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

namespace ohrp::sim {

// What the run does when the controller dies, hangs past --controller-timeout or detaches
// (the policy both producers share, shm_bridge/controller_loss.h): kEnd stops the run (exit code
// kExitControllerLost), kWait holds the robot, freezes time and waits for a new controller,
// kContinue keeps simulating with the last references held. A controller that hung is dropped
// (its slot freed): it exits with the controllers' "dropped" code should it run again.
using ControllerLoss = shm::ControllerLoss;

// An external push on the base: a wrench (world frame, at the base's centre of mass) applied
// from t0 to t1 of simulated time, e.g. to tilt the standing robot and release it. The wrench
// acts on every physics step that starts in [t0, t1) (to half a step), so a push lasts
// round((t1 - t0) / dt) steps and its impulse is force * that many steps * dt. Pushes whose
// windows overlap add.
struct Perturbation {
  double t0 = 0, t1 = 0;        // [s]
  double force[3] = {0, 0, 0};  // [N]
  double torque[3] = {0, 0, 0}; // [N m]
  bool active() const { return t1 > t0; }
};

// Parses one `--push` value "t0,t1,fx,fy,fz,tx,ty,tz" (8 finite numbers, t0 >= 0, t1 > t0).
// Returns false with `*error` saying what is wrong and how to write it.
bool ParsePerturbation(const std::string& spec, Perturbation* out, std::string* error);

// The `--push` value of `p`, "t0,t1,fx,fy,fz,tx,ty,tz" (%.17g: ParsePerturbation reads back the
// same numbers). The runner writes a scenario's pushes with it (a scenario's push is this window
// and force, given as a direction and an impulse or a force: runner/scenario.h's PushSpec).
std::string PerturbationText(const Perturbation& p);

// The total push wrench at simulated time `time` with physics step `dt`: the sum over the
// pushes whose window holds the step starting at `time` (see Perturbation). Writes 6 numbers
// (force then torque); no allocation.
void PushWrenchAt(const std::vector<Perturbation>& pushes, double time, double dt, double wrench[6]);

// True when push `p` acts on the physics step starting at `time` (step `dt`): the step starts
// in [t0, t1), to half a step (the rule of PushWrenchAt).
bool PushActiveAt(const Perturbation& p, double time, double dt);

// Puts the pushes' wrench for the step about to run on body `body`'s row of d->xfrc_applied.
// MuJoCo never clears xfrc_applied, so the row changes by the difference between the wrench
// wanted now and `pushed` (what the pushes put there before, updated here): other wrenches on
// the row stay. No allocation.
void ApplyPushes(const std::vector<Perturbation>& pushes, const mjModel* m, mjData* d, int body,
                 double pushed[6]);

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

// exit codes of sim_host
inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;           // bad option, model, keyframe or segment
inline constexpr int kExitMujocoError = 3;
inline constexpr int kExitDiverged = 4;
inline constexpr int kExitControllerLost = 5;  // lost (or never got) a controller, policy "end"
inline constexpr int kExitFell = 6;            // the robot fell (sim_host/fall.h), with --on-fall
                                               // end or continue; 4, 5 and 3 take precedence
inline constexpr int kExitOutputFailed = model::kExitOutputFailed;  // 9: the data log or the
                                               // summary could not be written completely
inline constexpr int kExitInterrupted = 130;   // SIGINT / SIGTERM: clean shutdown

// Runs one simulation as described by `options`; returns an exit code above. Prints set-up
// errors and the end-of-run report on stderr.
int RunHost(const HostOptions& options);

}  // namespace ohrp::sim
