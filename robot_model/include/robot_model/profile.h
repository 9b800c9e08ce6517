// The robot profile: one YAML file beside a robot's model (MJCF, OpenHRP VRML) that says what
// the applications need and the model does not, without editing the author's file. It is
// applied in memory when the model is loaded (robot_model/load.h: LoadMujocoModel takes a
// profile wherever it takes a model), so that sim_host, the controllers, hw_driver and the tools
// see the same augmented model and the existing conventions (docs/balance.md) find it:
//   - feet: a box geom <SIDE>_SOLE on each foot body (the soft contact and the support polygon);
//   - force_torque: a site with a <force> and a <torque> sensor on each foot (when the foot has
//     none);
//   - imu: a site with a <gyro>, an <accelerometer> and a <framequat> (when the model has none);
//   - stand: the keyframe "stand" (an existing keyframe copied, or joint values);
//   - base, actuators: a free joint and <motor>/<position> actuators (for a URDF robot).
// Keys, defaults and what each derives: docs/robots.md ("Robot profiles").
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

namespace ohrp::model {

struct ProfileFoot {
  std::string side;  // "left" or "right"
  std::string body;  // the foot's body
  bool sole_given = false;           // else derived from the body's lowest collision geoms
  std::array<double, 2> size{};      // sole rectangle [m] (x, y in the body frame)
  std::array<double, 3> centre{};    // centre of the sole's bottom face in the body frame [m]
  int line = 0;
};

struct ProfileSite {  // a sensor site to add
  std::string body;
  std::array<double, 3> pos{};  // in the body frame [m]
  int line = 0;
};

struct RobotProfile {
  std::string file;   // the profile's path
  std::string model;  // the model's path (resolved against the profile's folder)
  // "soft": the soles are the feet's contact (the foot bodies' own colliding geoms are switched
  // off); "native": the author's geoms stay the contact, the soles are non-colliding markers
  std::string contact = "soft";
  double sole_thickness = 0.01;  // [m]
  std::vector<ProfileFoot> feet;  // left, right
  bool force_torque = true;       // add F/T sites where a foot has none
  std::map<std::string, ProfileSite> force_torque_sites;  // side -> explicit site
  bool imu = true;                // add an IMU when the model has none
  bool imu_given = false;
  ProfileSite imu_site;           // body "" = the root body
  std::string stand_keyframe;     // copy this keyframe as "stand"
  std::map<std::string, double> stand_joints;  // or: these joint values (others at qpos0)
  bool stand_height_given = false;
  double stand_height = 0;        // base height; else derived (the soles' bottoms at z = 0)
  // a URDF robot: a free joint on the root body (MuJoCo fixes a URDF's root to the world), and
  // one actuator per joint
  bool free_base = false;
  std::string actuator_type;              // "" (none added), "motor" or "position"
  std::vector<std::string> actuator_joints;  // empty: every hinge and slide joint
  double actuator_kp = 0;                 // position: stiffness [N m/rad]
  double actuator_limit = 0;              // torque limit [N m], 0: none
  // listed for the applications, checked against the model, not used by the loader
  std::map<std::string, std::vector<std::string>> chains;  // e.g. left_leg: [joints...]
  std::map<std::string, std::vector<std::string>> groups;
  std::map<std::string, double> walking;                   // walking limits, by name
  // the soles' soft-contact parameters sim_host takes when no --contact-file is given (as `ohrp
  // identify` writes DIR/soles.yaml), resolved against the profile's folder; "": none
  std::string contact_file;
  // the joints as identified (armature, damping, frictionloss: robot_model/joint_params.h, as
  // `ohrp identify --joints --model` writes DIR/joints.yaml) sim_host applies when no
  // --joint-file is given, resolved against the profile's folder; "": none
  std::string joint_file;
  // the sensors as identified (bias and noise: robot_model/sensor_params.h, as `ohrp identify
  // --sensors` writes DIR/sensors.yaml) sim_host applies when no --sensor-file is given; "": none
  std::string sensor_file;
  // the robot's self-collision file (ohrp_selfcollision --model PROFILE), resolved against the
  // profile's folder: a controller's default when the segment's model hash is its; "": none
  std::string self_collision_file;
  // the joints' servo balance and walk use by default (their --servo-hz, --load-feedforward)
  double servo_frequency = 0;      // [Hz], 0: the producer's suggested gains
  bool load_feedforward = false;
  bool load_feedforward_given = false;  // the key is in the profile (else walk and balance derive it)
};

// True when `path` names a profile (".yaml" or ".yml").
bool IsProfilePath(const std::string& path);

// Reads a profile. False with `*error` = "FILE:LINE: KEY: what is wrong (what would do)".
bool ReadProfile(const std::string& path, RobotProfile* profile, std::string* error);

// The model of `profile` as MJCF text with the profile applied, and the name (in the model's own
// folder, so that its relative asset paths resolve) under which to give it to MuJoCo's VFS.
// False with `*error` listing everything the profile asks that the model cannot give.
bool ApplyProfile(const RobotProfile& profile, std::string* mjcf, std::string* vfs_name,
                  std::string* error);

// A draft profile for `model_path` (MJCF, VRML or URDF), each derived value commented with where
// it came from; `profile_path` is where it will be written (the model path is made relative to
// its folder). False with `*error` listing all that cannot be derived.
bool DraftProfile(const std::string& model_path, const std::string& profile_path,
                  std::string* yaml, std::string* error);

}  // namespace ohrp::model
