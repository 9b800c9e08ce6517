// A robot's sensors as identified (issue 35): per channel a constant bias and the std of white
// Gaussian noise, so that a simulated sensor reads like the robot's. `ohrp identify --sensors`
// writes the file (DIR/sensors.yaml); sim_host (`--sensor-file`, or a robot profile's
// `sensor_file:`) applies it to what its sensors report, and so does hw_emulator (`--sensor-file`,
// its sensor options --encoder-bias, --imu-bias, --ft-noise ... added: hw_driver/udp/src/
// plant_gap.h), both through model::ApplySensorModel (robot_model/sensors.h). SI units: rad, rad/s, m/s^2, N, N m.
//
//   # written by ohrp identify --sensors (the comments give the standard errors)
//   encoders:
//     LARM_ELBOW: {noise: 2.0e-4}           # a key left out is 0
//     RLEG_KNEE: {bias: 0.01, noise: 2.0e-4, velocity_noise: 1.0e-3, torque_noise: 0.1}
//   imus:
//     gyrometer: {gyro_bias: [0.01, -0.02, 0.005], gyro_noise: [0.003, 0.003, 0.003],
//                 accel_bias: [0.05, -0.1, 0.2], accel_noise: [0.03, 0.03, 0.03],
//                 orientation_noise: 1.0e-3}  # per axis of the orientation's error [rad]
//   force_torque:                           # fx fy fz [N] tx ty tz [N m]
//     rfsensor: {bias: [0, 0, 1.5, 0, 0, 0], noise: [2, 2, 2, 0.1, 0.1, 0.1]}
//
// A channel the file does not name reads as simulated. The reading is value + bias + std * n,
// n drawn from one seeded generator per SensorModel (the same seed, the same noise). sim_host's
// `--effects noise=on` is the same model with every sensor's noise set from the effect's
// standard deviations (sim_host/effects.h NoiseAsSensorParams), added to a file's.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "shm_bridge/layout.h"

namespace ohrp::model {

struct SensorParams {
  struct Encoder {
    std::string joint;
    double bias = 0, noise = 0;  // [rad]
    std::string note;            // written as a comment after the entry
    double velocity_noise = 0;   // [rad/s]
    double torque_noise = 0;     // [N m]
  };
  struct Imu {
    std::string name;
    double gyro_bias[3] = {}, gyro_noise[3] = {};    // [rad/s]
    double accel_bias[3] = {}, accel_noise[3] = {};  // [m/s^2]
    double orientation_noise = 0;  // per axis of the rotation vector of the orientation's error [rad]
    std::string note;
  };
  struct ForceTorque {
    std::string name;
    double bias[6] = {}, noise[6] = {};  // fx fy fz [N], tx ty tz [N m]
    std::string note;
  };
  std::vector<Encoder> encoders;
  std::vector<Imu> imus;
  std::vector<ForceTorque> forces;
};

// The largest magnitude each value may take (a mistake, not a sensor, beyond it).
inline constexpr double kMaxEncoderBias = 0.5, kMaxEncoderNoise = 0.1;
inline constexpr double kMaxVelocityNoise = 1.0, kMaxOrientationNoise = 0.1;
inline constexpr double kMaxGyro = 1.0, kMaxAccel = 5.0, kMaxForce = 500.0, kMaxTorque = 50.0;

// Reads the file. False with `*error` as "FILE:LINE: KEY: what is wrong (what would do)".
bool ReadSensorParamsFile(const std::string& path, SensorParams* p, std::string* error);

// Writes the file (`header` lines as comments on top, each entry's note after it).
bool WriteSensorParamsFile(const std::string& path, const SensorParams& p,
                           const std::vector<std::string>& header, std::string* error);

// The file's entries put in the robot's order (one entry per joint, IMU and F/T sensor, zeros
// where the file names none). False with `*error` naming an entry the robot does not have.
bool BindSensorParams(const SensorParams& file, const std::vector<std::string>& joints,
                      const std::vector<std::string>& imus, const std::vector<std::string>& forces,
                      SensorParams* by_index, std::string* error);

// `more`'s noise added to `p`'s (independent: the standard deviations add in quadrature; the
// biases add); both in the robot's order (BindSensorParams), `more` as large as `p` or larger.
void AddSensorParams(const SensorParams& more, SensorParams* p);

// "encoders: 29 noise, 1 bias; IMU gyrometer bias+noise; F/T rfsensor noise; ..."
std::string DescribeSensorParams(const SensorParams& p);

// The sensors as the robot gives them: `params` in the robot's order (BindSensorParams). The
// calls below neither allocate nor throw (the real-time path); an index beyond the params reads
// as simulated.
class SensorModel {
 public:
  SensorModel(SensorParams params, uint64_t seed) : p_(std::move(params)), rng_(seed) {}
  double Encoder(int j, double q) {
    if (j < 0 || j >= static_cast<int>(p_.encoders.size())) return q;
    const SensorParams::Encoder& e = p_.encoders[j];
    return q + e.bias + Noise(e.noise);
  }
  double Velocity(int j, double dq) {
    return j >= 0 && j < static_cast<int>(p_.encoders.size()) ? dq + Noise(p_.encoders[j].velocity_noise) : dq;
  }
  double Torque(int j, double tau) {
    return j >= 0 && j < static_cast<int>(p_.encoders.size()) ? tau + Noise(p_.encoders[j].torque_noise) : tau;
  }
  // the orientation (w x y z, world from IMU) turned by a small rotation in the IMU's frame
  // whose rotation vector has the IMU's orientation_noise per axis
  void Orientation(int u, double quat[4]);
  void Imu(int u, double gyro[3], double accel[3]);
  void ForceTorque(int f, double force[3], double torque[3]);
  // the references a servo acting on the true angle gets: a position reference in the encoder's
  // frame becomes one in the joint's (the bias taken out; kept within [q_min, q_max] when it was)
  void ToJointFrame(const double* q_min, const double* q_max, shm::CommandBlock* b) const;
  double encoder_bias(int j) const {
    return j >= 0 && j < static_cast<int>(p_.encoders.size()) ? p_.encoders[j].bias : 0.0;
  }
  const SensorParams& params() const { return p_; }

 private:
  double Noise(double std) { return std > 0 ? std * normal_(rng_) : 0.0; }
  SensorParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
};

}  // namespace ohrp::model
