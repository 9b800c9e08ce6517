// Sensor simulation (see sensors.h).
#include "robot_model/sensors.h"

#include <cstring>
#include <limits>

#include "robot_model/model_hash.h"

namespace ohrp::model {
namespace {

void CopyName(char (&dst)[shm::kNameLen], const std::string& src) {
  std::memset(dst, 0, sizeof(dst));
  std::strncpy(dst, src.c_str(), sizeof(dst) - 1);
}

}  // namespace

shm::ProducerConfig MakeProducerConfig(const RobotMap& robot, const mjModel* m,
                                       const std::string& segment_name, double physics_period,
                                       double control_period) {
  shm::ProducerConfig c;
  c.segment_name = segment_name;
  c.kind = shm::ProducerKind::kSimulation;
  c.robot_name = robot.name;
  for (const JointMap& j : robot.joints) {
    c.joint_names.push_back(j.name);
    c.q_min.push_back(j.q_min);
    c.q_max.push_back(j.q_max);
    c.tau_max.push_back(j.tau_max);
    c.default_kp.push_back(j.default_kp);
    c.default_kd.push_back(j.default_kd);
  }
  for (const ForceSensorMap& f : robot.forces) c.force_names.push_back(f.name);
  for (const ImuMap& i : robot.imus) c.imu_names.push_back(i.name);
  for (const PassiveJointMap& p : robot.passive) c.passive_names.push_back(p.name);
  for (const CameraMap& cam : robot.cameras) {
    shm::CameraInfo info{};
    CopyName(info.name, cam.name);
    info.width = 640;  // offscreen buffer size of the cameras (rendering comes with vision)
    info.height = 480;
    info.fovy = m->cam_fovy[cam.camera_id];
    for (int k = 0; k < 3; ++k) info.p_BC[k] = m->cam_pos[3 * cam.camera_id + k];
    c.cameras.push_back(info);
  }
  c.physics_period = physics_period;
  c.control_period = control_period;
  FillModelIdentity(m, robot, &c);
  return c;
}

void FillSensors(const RobotMap& robot, const mjModel* m, const mjData* d,
                 shm::SensorBlock* out) {
  FillSensors(robot, m, d, SensorSelection{}, out);
}

void FillSensors(const RobotMap& robot, const mjModel* m, const mjData* d,
                 const SensorSelection& sel, shm::SensorBlock* out) {
  constexpr double kOff = std::numeric_limits<double>::quiet_NaN();  // not measured
  const int n = static_cast<int>(robot.joints.size());
  for (int i = 0; i < n; ++i) {
    const JointMap& j = robot.joints[i];
    out->q[i] = sel.q ? d->qpos[j.qpos_adr] : kOff;
    out->dq[i] = sel.dq ? d->qvel[j.dof_adr] : kOff;
    out->tau[i] = sel.tau ? j.law.gear * d->actuator_force[j.actuator_id] : kOff;  // joint torque
  }
  // passive joints: read like the encoders of the driven ones
  for (size_t i = 0; i < robot.passive.size(); ++i) {
    const PassiveJointMap& p = robot.passive[i];
    out->passive_q[i] = sel.q ? d->qpos[p.qpos_adr] : kOff;
    out->passive_dq[i] = sel.dq ? d->qvel[p.dof_adr] : kOff;
  }
  // MuJoCo's force/torque sensors read what the parent exerts on the child; the segment
  // carries OpenHRP's convention (child on parent), hence the sign
  for (size_t f = 0; f < robot.forces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      out->force[f].force[k] = sel.force_torque ? -d->sensordata[robot.forces[f].force_adr + k] : kOff;
      out->force[f].torque[k] = sel.force_torque ? -d->sensordata[robot.forces[f].torque_adr + k] : kOff;
    }
  }
  for (size_t i = 0; i < robot.imus.size(); ++i) {
    const ImuMap& imu = robot.imus[i];
    for (int k = 0; k < 3; ++k) {
      out->imu[i].gyro[k] = sel.gyro ? d->sensordata[imu.gyro_adr + k] : kOff;
      out->imu[i].accel[k] = sel.accel ? d->sensordata[imu.accel_adr + k] : kOff;
    }
    if (!sel.orientation) {
      for (int k = 0; k < 4; ++k) out->imu[i].quat_WI[k] = kOff;
    } else if (imu.quat_adr >= 0) {
      for (int k = 0; k < 4; ++k) out->imu[i].quat_WI[k] = d->sensordata[imu.quat_adr + k];
    } else {
      mju_mat2Quat(out->imu[i].quat_WI, d->site_xmat + 9 * imu.site_id);
    }
  }
  // ground truth of the base, for logs and checks only
  if (robot.base_body >= 0) {
    const double* qpos = d->qpos + robot.base_qpos;
    const double* qvel = d->qvel + robot.base_dof;
    for (int k = 0; k < 3; ++k) out->sim_truth.p_WB[k] = qpos[k];
    for (int k = 0; k < 4; ++k) out->sim_truth.quat_WB[k] = qpos[3 + k];
    for (int k = 0; k < 3; ++k) out->sim_truth.v_WB[k] = qvel[k];
    // the free joint's angular velocity is in the body frame: rotate it to the world
    const double* R_WB = d->xmat + 9 * robot.base_body;
    mju_mulMatVec(out->sim_truth.w_WB, R_WB, qvel + 3, 3, 3);
  }
  (void)m;
}

bool BindSensorParams(const SensorParams& file, const RobotMap& robot, SensorParams* by_index,
                      std::string* error) {
  std::vector<std::string> joints, imus, forces;
  for (const JointMap& j : robot.joints) joints.push_back(j.name);
  for (const auto& u : robot.imus) imus.push_back(u.name);
  for (const auto& f : robot.forces) forces.push_back(f.name);
  return BindSensorParams(file, joints, imus, forces, by_index, error);
}

void ApplySensorModel(const RobotMap& robot, const SensorSelection& selection,
                      SensorModel* sensors, shm::SensorBlock* s) noexcept {
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

}  // namespace ohrp::model
