// The sensor selection of an effects plan, the noise effect as sensor parameters, and the
// sensor model on a published block (effects.h).
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

void ApplySensorModel(const model::RobotMap& robot, const model::SensorSelection& selection,
                      model::SensorModel* sensors, shm::SensorBlock* s) noexcept {
  const int nj = static_cast<int>(robot.joints.size());
  if (selection.q)
    for (int j = 0; j < nj; ++j) s->q[j] = sensors->Encoder(j, s->q[j]);
  if (selection.dq)
    for (int j = 0; j < nj; ++j) s->dq[j] = sensors->Velocity(j, s->dq[j]);
  if (selection.tau)
    for (int j = 0; j < nj; ++j) s->tau[j] = sensors->Torque(j, s->tau[j]);
  if (selection.force_torque)
    for (size_t f = 0; f < robot.forces.size(); ++f)
      sensors->ForceTorque(static_cast<int>(f), s->force[f].force, s->force[f].torque);
  for (size_t u = 0; u < robot.imus.size(); ++u) {
    if (selection.gyro || selection.accel) {
      double unused[3] = {};  // a sensor the run does not give stays unread (its draws still made)
      sensors->Imu(static_cast<int>(u), selection.gyro ? s->imu[u].gyro : unused,
                   selection.accel ? s->imu[u].accel : unused);
    }
    if (selection.orientation) sensors->Orientation(static_cast<int>(u), s->imu[u].quat_WI);
  }
}

}  // namespace ohrp::sim
