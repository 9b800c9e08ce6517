// The sensor selection of an effects plan and the noise effect as sensor parameters (effects.h).
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

model::SensorParams NoiseAsSensorParams(const NoiseOptions& o, const model::RobotMap& robot) {
  model::SensorParams p;
  for (const model::JointMap& j : robot.joints) {
    model::SensorParams::Encoder e;
    e.joint = j.name;
    e.noise = o.q;
    e.velocity_noise = o.dq;
    e.torque_noise = o.tau;
    p.encoders.push_back(e);
  }
  for (const auto& imu : robot.imus) {
    model::SensorParams::Imu u;
    u.name = imu.name;
    for (int k = 0; k < 3; ++k) u.gyro_noise[k] = o.gyro, u.accel_noise[k] = o.accel;
    u.orientation_noise = o.orientation;
    p.imus.push_back(u);
  }
  for (const auto& force : robot.forces) {
    model::SensorParams::ForceTorque f;
    f.name = force.name;
    for (int k = 0; k < 3; ++k) f.noise[k] = o.force, f.noise[3 + k] = o.torque;
    p.forces.push_back(f);
  }
  return p;
}

}  // namespace ohrp::sim
