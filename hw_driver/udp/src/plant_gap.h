// hw_emulator's gap between the model and the robot: what a real robot has that the model does
// not, set from the command line so that identification (issue 35) is tested on values it is
// not told.
//
//   --friction JOINT|all=COULOMB,VISCOUS  the joint's dof gets MuJoCo frictionloss COULOMB [N m]
//                                         and damping VISCOUS [N m s/rad] (replacing the model's;
//                                         see model::kFrictionImpedance)
//   --armature JOINT|all=X                X [kg m^2] added to the dof's armature (rotor inertia)
//   --delay-ms X                          the motor boards apply the commands X ms (a whole number
//                                         of board cycles) after they arrive; e-stop, board resets
//                                         and the boards' own holds act at once
//   --encoder-bias JOINT|all=X            the joint's encoder reads q + X [rad]; the board's PD
//                                         acts on what it reads (a position reference r holds the
//                                         joint at r - X)
//   --encoder-noise X                     white noise of std X [rad] on every reported joint
//                                         position (the board's PD uses the noise-free reading)
//   --imu-bias G,A | GX,GY,GZ,AX,AY,AZ    added to the IMUs' rates [rad/s] and specific forces [m/s^2]
//   --imu-noise G,A                       white noise std on each rate / acceleration axis
//   --ft-noise F,T                        white noise std on each force [N] / torque [N m] axis
//   --ft-bias F,T | FX,FY,FZ,TX,TY,TZ     added to every F/T sensor's force [N] / torque [N m]
// JOINT is a joint's name or index; later entries override earlier ones (all=..., then one joint).
//   --sensor-file FILE                    the sensors as identified (ohrp identify --sensors'
//                                         sensors.yaml, sim_host --sensor-file's format): per
//                                         joint encoder bias and noise, velocity and torque noise,
//                                         per IMU gyro, accelerometer and orientation bias/noise,
//                                         per F/T sensor offset and noise, added to the above
// Passive joints are reported as simulated.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "robot_model/sensor_params.h"
#include "robot_model/sensors.h"
#include "shm_bridge/layout.h"

struct mjModel_;
typedef struct mjModel_ mjModel;
struct mjData_;
typedef struct mjData_ mjData;

namespace ohrp::hw::udp {

inline constexpr double kMaxDelayMs = 1000.0;

// the options as given on the command line
struct GapOptions {
  std::vector<std::string> friction, armature, encoder_bias;
  double delay_ms = 0;
  double encoder_noise = 0;
  std::string imu_bias, imu_noise, ft_noise, ft_bias;
  std::string sensor_file;
};

struct JointGap {
  double coulomb = -1, viscous = -1;  // < 0: the model's
  double armature = 0;                // added [kg m^2]
  double bias = 0;                    // encoder bias [rad]
};

struct PlantGap {
  std::vector<JointGap> joint;  // per robot joint
  int delay_cycles = 0;
  double encoder_noise = 0;
  double gyro_bias[3] = {}, accel_bias[3] = {};
  double gyro_noise = 0, accel_noise = 0, force_noise = 0, torque_noise = 0;
  double force_bias[3] = {}, torque_bias[3] = {};
};

// Parses the options for a robot with these joints and board cycle `period` [s]. Returns false
// with `*error` naming the option, the value and what is expected.
bool ParseGap(const GapOptions& o, const std::vector<std::string>& joint_names, double period,
              PlantGap* gap, std::string* error);

// Sets friction loss (and its impedance), damping and armature of each joint's dof (dof_adr[j])
// on the model; `data` is used to recompute the model's constants when an armature changes.
// Set-up only.
void ApplyGapToModel(const PlantGap& gap, const std::vector<int>& dof_adr, mjModel* m,
                     mjData* data);

// One line for the start-up message ("none" when the robot is the model).
std::string DescribeGap(const PlantGap& gap);

// The sensors as the robot's give them: bias and white noise through the one sensor model
// (robot_model/sensors.h ApplySensorModel, which sim_host uses on what it publishes: the same
// draws for the same parameters and seed); no allocation after construction.
class SensorGap {
 public:
  // `imus`, `forces`: how many the robot has (each gets the gap's IMU / F/T bias and noise);
  // `file`: --sensor-file's entries in the robot's order (model::BindSensorParams; empty: none),
  // added to the options' (biases add, noise in quadrature)
  SensorGap(const PlantGap& gap, size_t imus, size_t forces, const model::SensorParams& file,
            uint64_t seed);
  // every reading of `s` (FillSensors's) as the boards report it
  void Apply(const model::RobotMap& robot, shm::SensorBlock* s) {
    model::ApplySensorModel(robot, model::SensorSelection{}, &model_, s);
  }
  // the references the boards' PD acts on: a position reference in the encoder's frame becomes
  // one in the joint's (bias taken out; kept within [q_min, q_max] when it was)
  void ToJointFrame(const double* q_min, const double* q_max, shm::CommandBlock* b) const {
    model_.ToJointFrame(q_min, q_max, b);
  }
  const model::SensorParams& params() const { return model_.params(); }

 private:
  model::SensorModel model_;
};

}  // namespace ohrp::hw::udp
