// Only the effects a scene calls for: which of the things sim_host can compute are on, and why.
//
// Every effect (gravity, joint limits, passive springs and dampers, MuJoCo's native contact per
// body pair, MuJoCo's contact within the robot (self_contact), the self-collision report, the
// soft-foot contact, each sensor kind, sensor noise, cameras, the
// data log's channels) is on only when the scene (the MJCF), the contact choice (FeetOptions)
// or a request (`sim_host --effects`, the scenario key `effects:`) calls for it, directly or
// because something that is on needs it. ResolveEffects decides and records the reason of each
// decision; ApplyEffects puts the decision into the mjModel (MuJoCo 2.2.2 disable flags, the
// stage of each MuJoCo sensor, a contact filter for switched-off pairs); the noise is the
// sensor model's (NoiseAsSensorParams). docs/effects.md lists the effects, their defaults and
// their dependencies.
//
// Resolution rules, in order:
//   1. each effect starts from what the scene declares (its default) or from its request;
//      a request to switch on what the scene does not declare (or cannot be computed) is an
//      error;
//   2. an effect that is on switches on what it needs ("needed by X"), unless that was
//      switched off by a request: then a requested X is an error (conflicting requests) and a
//      default X goes off ("needs Y, which was switched off");
//   3. repeated until nothing changes.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "shm_bridge/layout.h"
#include "sim_host/feet.h"
#include "robot_model/model.h"
#include "robot_model/sensor_params.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::sim {

enum class Effect : int {
  kGravity,          // gravitational forces (mjDSBL_GRAVITY)
  kJointLimits,      // joint and tendon limit constraints (mjDSBL_LIMIT)
  kPassive,          // joint/tendon springs and dampers, fluid forces (mjDSBL_PASSIVE)
  kNativeContact,    // MuJoCo's contact, all pairs (mjDSBL_CONTACT); per pair: ContactPair
  kSelfContact,      // MuJoCo's contact between two bodies of the same robot (contact filter)
  kSelfCollision,    // the robot's link pairs checked each control cycle with the controllers'
                     // checker, contacts reported after the run (sim_host/self_collision_watch.h)
  kSoftContact,      // the soft-foot contact under the soles (--contact soft)
  kEncoders,         // joint positions q in the segment
  kJointVelocities,  // joint velocities dq
  kJointTorques,     // joint torques tau (the servo's output)
  kForceTorque,      // the F/T sensors (MuJoCo force + torque sensors)
  kGyro,             // the IMUs' angular velocity (MuJoCo gyro)
  kAccelerometer,    // the IMUs' linear acceleration (MuJoCo accelerometer)
  kOrientation,      // the IMUs' orientation (framequat, or the site's frame)
  kRnePost,          // mj_rnePostConstraint: body accelerations and internal forces
  kOtherSensors,     // MuJoCo sensors of the scene that sim_host does not publish
  kNoise,            // Gaussian sensor noise (off unless asked)
  kCameras,          // images of the scene's cameras
  kLog,              // the CSV data log (--log)
  kLogBase,          // log columns: base pose and velocity (ground truth)
  kLogJoints,        // log columns: q, qref, tau
  kLogForceTorque,   // log columns: F/T
  kLogImu,           // log columns: IMU
  kCount
};
inline constexpr int kEffectCount = static_cast<int>(Effect::kCount);

// "gravity", "joint_limits", ... (the names of --effects and docs/effects.md)
const char* EffectName(Effect e);
bool ParseEffectName(const std::string& name, Effect* e);

// Standard deviations of the Gaussian noise per sensor kind (SI units) and the seed of its
// generator. The defaults are documented in docs/effects.md.
struct NoiseOptions {
  double q = 1e-4;            // joint position [rad]
  double dq = 1e-3;           // joint velocity [rad/s]
  double tau = 0.1;           // joint torque [N m]
  double force = 1.0;         // F/T force [N]
  double torque = 0.1;        // F/T torque [N m]
  double gyro = 5e-3;         // angular velocity [rad/s]
  double accel = 0.05;        // linear acceleration [m/s^2]
  double orientation = 1e-3;  // rotation angle of the orientation error, per axis [rad]
  uint64_t seed = 1;          // same seed, same noise
};

// What the user asked for: per effect none / off / on, per contact pair, noise settings.
struct EffectRequests {
  std::array<int8_t, kEffectCount> request;  // -1 none, 0 off, 1 on
  struct Pair {
    std::string body1, body2;  // body names as in the MJCF ("world" for the static world)
    bool on = false;
  };
  std::vector<Pair> pairs;
  NoiseOptions noise;
  EffectRequests() { request.fill(-1); }
};

// Parses a comma-separated list, the syntax of `sim_host --effects` and of the scenario key:
//   NAME=on|off                      an effect (names: EffectName)
//   contact:BODY1/BODY2=on|off       MuJoCo's contact between two bodies
//   noise.KIND=STD                   noise standard deviation (q dq tau force torque gyro accel
//                                    orientation), SI units
//   noise.seed=N                     seed of the noise generator
// Adds to `*out` (later entries win). Returns false with `*error` naming the bad entry.
bool ParseEffectRequests(const std::string& spec, EffectRequests* out, std::string* error);

struct EffectState {
  bool on = false;
  bool declared = false;  // the scene has it (or it can be computed at all)
  std::string reason;     // who asked, or which effect needs it, or why it is off
};

// MuJoCo's contact between two bodies: on when the scene lets some of their geoms collide
// (contype/conaffinity, not excluded, not parent-child) and nothing else handles it.
struct ContactPair {
  int body1 = -1, body2 = -1;  // body ids, body1 < body2
  std::string name;            // "BODY1/BODY2"
  int geom_pairs = 0;          // geom pairs that can collide
  bool self = false;           // both bodies belong to the same robot (one kinematic tree)
  bool soles = false;          // a sole of the soft-foot contact is in it
  bool on = false;
  std::string reason;
};

// The resolved effects.
struct EffectsPlan {
  std::array<EffectState, kEffectCount> effects;
  std::vector<ContactPair> pairs;
  NoiseOptions noise;
  bool on(Effect e) const { return effects[static_cast<int>(e)].on; }
  const EffectState& operator[](Effect e) const { return effects[static_cast<int>(e)]; }
  // the table of `sim_host --explain`: every effect and contact pair, on/off and why
  std::string Table() const;
  // two lines for the start of a run: what is on, what is off
  std::string Short() const;
};

// Decides every effect for the model `m` as loaded (before SetUpFeet changes it), the robot
// found in it, the contact choice, whether a data log is written, and the requests. Returns
// false with `*error` saying what cannot be done (e.g. switching on cameras, conflicting
// requests, a contact pair the scene does not have).
bool ResolveEffects(const mjModel* m, const model::RobotMap& robot, const FeetOptions& feet,
                    bool log, const EffectRequests& requests, EffectsPlan* plan,
                    std::string* error);

// Puts `plan` into the model: disable flags for gravity, limits, passive forces, contact and
// sensors; each MuJoCo sensor that no effect reads is taken out of MuJoCo's sensor stages
// (sensor_needstage = mjSTAGE_NONE: never computed, its sensordata stays as it was); a
// contact filter (mjcb_contactfilter, process-wide, for this model only) when a contact pair
// or self_contact is switched off while native contact is on. (self_collision is no physics:
// the host runs its SelfCollisionWatch when it is on.) Call after SetUpFeet and
// before the first mj_forward. `m` must outlive the filter (ClearContactFilter removes it).
void ApplyEffects(const EffectsPlan& plan, const model::RobotMap& robot, mjModel* m);
void ClearContactFilter();

// Which of the segment's sensor fields FillSensors measures (the others are NaN).
model::SensorSelection SelectSensors(const EffectsPlan& plan);

// `--effects noise=on` as sensor parameters (robot_model/sensor_params.h): every joint, IMU and
// F/T sensor of the robot, in the robot's order, with the effect's standard deviations and no
// bias. sim_host adds them to a sensor file's (AddSensorParams) and runs one SensorModel.
model::SensorParams NoiseAsSensorParams(const NoiseOptions& options, const model::RobotMap& robot);

// The sensor model on a published block: robot_model/sensors.h (hw_emulator's too).
using model::ApplySensorModel;

}  // namespace ohrp::sim
