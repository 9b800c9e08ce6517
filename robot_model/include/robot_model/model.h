// Loading a scene and finding the robot in it: which MuJoCo joints, actuators and sensors make
// up the joints, force/torque sensors, IMUs and cameras of the robot's segment.
//
// Conventions read from the MJCF (see mjcf/hrp1s/README.md):
//   - the robot's joints are the targets of its actuators, in actuator order (this is the
//     joint-id order of the segment), one actuator per hinge or slide joint: <motor> with any
//     gear, <position>, <velocity>, or <general> with a fixed gain and an affine bias
//     (actuator.h says how a joint torque becomes the actuator's control); the torque limit is
//     what ctrlrange and forcerange allow;
//   - the robot's other hinge and slide joints (in the base's subtree, or anywhere when the
//     robot is fixed) are passive: published read-only (e.g. Cassie's shin and tarsus);
//   - a force/torque sensor is a `<force>` and a `<torque>` sensor on the same site; its name
//     is the site's name;
//   - an IMU is a `<gyro>` and an `<accelerometer>` on the same site (plus an optional
//     `<framequat>` of that site); its name is the site's name;
//   - the base is the body of the first free joint.
#pragma once

#include <mujoco/mujoco.h>

#include "robot_model/actuator.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ohrp::model {

struct JointMap {
  std::string name;
  int joint_id = -1;     // MuJoCo joint id
  int actuator_id = -1;  // MuJoCo actuator id (drives this joint)
  int qpos_adr = -1;
  int dof_adr = -1;
  double q_min = 0, q_max = 0;  // limits [rad or m]; +-kNoLimit when unlimited
  double tau_max = 0;           // joint torque limit [N m or N]; kNoLimit when unbounded
  ActuatorLaw law;              // how a joint torque becomes the actuator's ctrl
  double default_kp = 0;        // suggested PD gains (see SuggestGains in model.cc)
  double default_kd = 0;
};

// A hinge or slide joint of the robot that no actuator drives: read, never commanded.
struct PassiveJointMap {
  std::string name;
  int joint_id = -1;
  int qpos_adr = -1;
  int dof_adr = -1;
};

struct ForceSensorMap {
  std::string name;
  int site_id = -1;
  int force_adr = -1;   // sensordata address of the <force> sensor (3 values)
  int torque_adr = -1;  // sensordata address of the <torque> sensor (3 values)
};

struct ImuMap {
  std::string name;
  int site_id = -1;
  int gyro_adr = -1;
  int accel_adr = -1;
  int quat_adr = -1;  // -1: orientation computed from the site's frame
};

struct CameraMap {
  std::string name;
  int camera_id = -1;
  int body_id = -1;
};

// The robot as the segment sees it.
struct RobotMap {
  std::string name;
  int base_body = -1;   // body of the first free joint, -1 if the robot is fixed
  int base_qpos = -1;
  int base_dof = -1;
  std::vector<JointMap> joints;
  std::vector<PassiveJointMap> passive;  // joint order of the model
  std::vector<ForceSensorMap> forces;
  std::vector<ImuMap> imus;
  std::vector<CameraMap> cameras;
  double total_mass = 0;  // [kg], all bodies but the world
  // sensors of the model the segment does not carry, each with why and what would carry it
  // (a <force> without a <torque> on its site, a <gyro> without an <accelerometer>, a sensor
  // on something else than a site): never dropped without a word
  std::vector<std::string> unpublished;
};

inline constexpr double kNoLimit = 1e9;

// Owns an mjModel and the mjData stepping it.
class Scene {
 public:
  // Loads an MJCF file. On failure returns null and sets `*error` to MuJoCo's text prefixed by
  // the file name.
  static std::unique_ptr<Scene> Load(const std::string& path, std::string* error);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  mjModel* m() const { return m_; }
  mjData* d() const { return d_; }
  const std::string& path() const { return path_; }

  // Resets to the model's initial state or, when `keyframe` is not empty, to that keyframe.
  // Returns false (and sets `*error`) when the keyframe does not exist.
  bool Reset(const std::string& keyframe, std::string* error);

 private:
  Scene() = default;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::string path_;
};

// Builds the segment's view of the robot. Returns false with `*error` set when the model has no
// robot the segment can carry (no actuators, an actuator whose law cannot be inverted (see
// ReadActuatorLaw), two actuators on one joint, too many joints or sensors).
bool MapRobot(const mjModel* m, RobotMap* robot, std::string* error);

// The hinge and slide joints' positions in keyframe `key` of `m`, by joint name, in joint order
// (e.g. for `posture --keyframe`). Returns false with `*error` naming the keyframe and the ones
// the model has when it has no keyframe of that name.
bool KeyframeJointPositions(const mjModel* m, const std::string& key,
                            std::vector<std::pair<std::string, double>>* out, std::string* error);

// The lines of `sim_host --explain` about the robot's joints: for each joint, its actuator, the
// actuator's type and how a joint torque becomes its control (ActuatorLaw::Describe), the
// joint's torque limit; then the passive joints, published read-only.
std::string DescribeActuation(const RobotMap& robot);

// Installs MuJoCo error and warning handlers that never wait on stdin: errors print the message
// and run `on_fatal` (which must not return), warnings are counted (see WarningCount).
void InstallMujocoHandlers(void (*on_fatal)(const char* message));
long WarningCount();
const char* LastWarning();

}  // namespace ohrp::model
