// The sensor selection of an effects plan and the Gaussian sensor noise (effects.h).
#include <cmath>

#include "sim_host/effects.h"

namespace ohrp::sim {

model::SensorSelection SelectSensors(const EffectsPlan& p) {
  model::SensorSelection s;
  s.q = p.on(Effect::kEncoders);
  s.dq = p.on(Effect::kJointVelocities);
  s.tau = p.on(Effect::kJointTorques);
  s.force_torque = p.on(Effect::kForceTorque);
  s.gyro = p.on(Effect::kGyro);
  s.accel = p.on(Effect::kAccelerometer);
  s.orientation = p.on(Effect::kOrientation);
  return s;
}

SensorNoise::SensorNoise(const NoiseOptions& options, const model::SensorSelection& selection)
    : o_(options), sel_(selection), rng_(options.seed) {}

void SensorNoise::Apply(const model::RobotMap& robot, shm::SensorBlock* s) {
  const int nj = static_cast<int>(robot.joints.size());
  if (sel_.q && o_.q > 0)
    for (int i = 0; i < nj; ++i) s->q[i] += o_.q * Gauss();
  if (sel_.dq && o_.dq > 0)
    for (int i = 0; i < nj; ++i) s->dq[i] += o_.dq * Gauss();
  if (sel_.tau && o_.tau > 0)
    for (int i = 0; i < nj; ++i) s->tau[i] += o_.tau * Gauss();
  if (sel_.force_torque) {
    for (size_t f = 0; f < robot.forces.size(); ++f) {
      for (int k = 0; k < 3; ++k) {
        if (o_.force > 0) s->force[f].force[k] += o_.force * Gauss();
        if (o_.torque > 0) s->force[f].torque[k] += o_.torque * Gauss();
      }
    }
  }
  for (size_t u = 0; u < robot.imus.size(); ++u) {
    shm::Imu& imu = s->imu[u];
    for (int k = 0; k < 3; ++k) {
      if (sel_.gyro && o_.gyro > 0) imu.gyro[k] += o_.gyro * Gauss();
      if (sel_.accel && o_.accel > 0) imu.accel[k] += o_.accel * Gauss();
    }
    if (sel_.orientation && o_.orientation > 0) {
      // a small rotation, its vector Gaussian per axis, applied in the IMU's frame
      double v[3] = {o_.orientation * Gauss(), o_.orientation * Gauss(), o_.orientation * Gauss()};
      const double angle = mju_norm3(v);
      double dq[4] = {1, 0, 0, 0};
      if (angle > 0) {
        const double sn = std::sin(0.5 * angle) / angle;
        dq[0] = std::cos(0.5 * angle);
        for (int k = 0; k < 3; ++k) dq[1 + k] = sn * v[k];
      }
      double q[4];
      mju_mulQuat(q, imu.quat_WI, dq);
      mju_normalize4(q);
      for (int k = 0; k < 4; ++k) imu.quat_WI[k] = q[k];
    }
  }
}

}  // namespace ohrp::sim
