// The balance controller (see balance.h).
#include "controllers/balance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "controllers/posture.h"
#include "controllers/ramp.h"
#include "robot_model/model_hash.h"

#ifndef OHRP_SOURCE_DIR
#error "OHRP_SOURCE_DIR must be defined by the build"
#endif

namespace ohrp::controllers {
namespace {

// torso joints: on the path from the base to the IMU, turning about the base's y (pitch) or x
// (roll) in the reference configuration
constexpr double kAxisAlignment = 0.95;  // |cos| between the joint axis and the base axis [-]
constexpr double kMaxWaitForContact = 1.0;  // [s] before the ramp starts without both soles down
constexpr double kEstimatorSettle = 0.3;    // [s] of estimation before the soles' tilt is trusted

ConfigStatus CheckOptions(const BalanceOptions& o) {
  auto bad = [](const std::string& what) { return ConfigStatus::Fail(ConfigError::kOption, what); };
  if (!(std::isfinite(o.ramp) && o.ramp >= 0)) return bad("--ramp must be a finite time >= 0 s");
  if (!(std::isfinite(o.settle) && o.settle >= 0)) return bad("--settle must be a finite time >= 0 s");
  const StabilizerGains& g = o.gains;
  if (!(std::isfinite(g.k_dcm) && g.k_dcm >= 0)) return bad("--k-dcm must be finite and >= 0 [1/s]");
  if (!(std::isfinite(g.ankle_damping) && g.ankle_damping > 0))
    return bad("--ankle-damping must be finite and > 0 [N m s/rad]");
  if (!(std::isfinite(g.z_damping) && g.z_damping > 0))
    return bad("--z-damping must be finite and > 0 [N s/m]");
  if (!(std::isfinite(g.ankle_recovery) && g.ankle_recovery > 0 && std::isfinite(g.z_recovery) &&
        g.z_recovery > 0))
    return bad("--ankle-recovery must be finite and > 0 [s]");
  if (!(std::isfinite(g.hip_gain) && g.hip_gain >= 0)) return bad("--hip-gain must be finite and >= 0");
  if (!(std::isfinite(g.support_margin) && g.support_margin >= 0))
    return bad("--support-margin must be finite and >= 0 [m]");
  return ConfigStatus::Ok();
}

// the joint of `chain` whose axis (in W at the reference configuration) is closest to `axis`
int FindTorsoJoint(const model::Kinematics& kin, const std::vector<int>& chain,
                   const Eigen::Vector3d& axis) {
  const mjModel* m = kin.m();
  for (int j : chain) {
    const int jid = kin.robot().joints[j].joint_id;
    const int body = m->jnt_bodyid[jid];
    const Eigen::Vector3d a_local(m->jnt_axis[3 * jid], m->jnt_axis[3 * jid + 1],
                                  m->jnt_axis[3 * jid + 2]);
    const Eigen::Vector3d a_W = kin.R_WBody(body) * a_local;
    if (std::abs(a_W.dot(axis)) > kAxisAlignment) return j;
  }
  return -1;
}

Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }

}  // namespace

std::string DefaultModelFile() { return std::string(OHRP_SOURCE_DIR) + "/mjcf/hrp1s/hrp1s.xml"; }

const char* HoldReasonName(HoldReason r) {
  switch (r) {
    case HoldReason::kNone: return "none";
    case HoldReason::kNonFiniteSensors: return "non-finite sensors";
    case HoldReason::kBoardFault: return "board fault reported by the producer";
    case HoldReason::kEstimatorFailed: return "state estimator failed";
    case HoldReason::kStaleSensors: return "stale sensors (their time stopped advancing)";
  }
  return "?";
}

//---------------- set-up ----------------

std::unique_ptr<BalanceController> BalanceController::Create(const BalanceOptions& options,
                                                             ConfigStatus* status) {
  *status = CheckOptions(options);
  if (!status->ok()) return nullptr;
  BalanceOptions o = options;
  if (o.model.empty()) o.model = DefaultModelFile();
  if (o.pose_file.empty()) o.pose_file = DefaultPoseFile();
  Pose pose;
  *status = LoadPoseFile(o.pose_file, &pose);
  if (!status->ok()) return nullptr;
  std::string error;
  auto kin_est = model::Kinematics::Load(o.model, &error);
  auto kin_ik = kin_est ? model::Kinematics::Load(o.model, &error) : nullptr;
  if (!kin_est || !kin_ik) {
    *status = ConfigStatus::Fail(ConfigError::kFile, "--model: " + error);
    return nullptr;
  }
  // what balance needs of the robot
  const model::Kinematics& k = *kin_est;
  std::string missing;
  if (!k.floating()) missing += " a floating base (a free joint);";
  if (k.left_sole() < 0 || k.right_sole() < 0) {
    missing += " two soles (box geoms named *_SOLE);";
  } else {
    for (int side : {k.left_sole(), k.right_sole()}) {
      if (k.soles()[side].force_sensor < 0)
        missing += " a force/torque sensor above sole " + k.soles()[side].name + ";";
    }
  }
  if (k.robot().imus.empty()) missing += " an IMU (gyro + accelerometer on one site);";
  if (!missing.empty()) {
    missing.pop_back();
    *status = ConfigStatus::Fail(ConfigError::kMismatch, "balance needs" + missing + ", and the robot of " +
                                                             o.model + " has not");
    return nullptr;
  }
  return std::unique_ptr<BalanceController>(
      new BalanceController(o, std::move(pose), std::move(kin_est), std::move(kin_ik)));
}

BalanceController::BalanceController(const BalanceOptions& options, Pose pose,
                                     std::unique_ptr<model::Kinematics> kin_est,
                                     std::unique_ptr<model::Kinematics> kin_ik)
    : options_(options),
      pose_(std::move(pose)),
      kin_est_(std::move(kin_est)),
      kin_ik_(std::move(kin_ik)),
      stabilizer_(options.gains) {}

ConfigStatus BalanceController::on_configure(const shm::SegmentHeader& header) {
  if (ConfigStatus s = CheckOptions(options_); !s.ok()) return s;
  // the producer's robot must be the one of --model
  const std::string diff = model::CheckModelMatches(kin_est_->m(), kin_est_->robot(), header);
  if (!diff.empty()) {
    return ConfigStatus::Fail(ConfigError::kMismatch,
                              "--model " + options_.model + ": " + diff);
  }
  if (ConfigStatus s = ResolvePose(pose_, joint_names(), &target_); !s.ok()) return s;
  if (ConfigStatus s = CheckWithinLimits(header, target_.data(), pose_.source); !s.ok()) return s;

  const model::Kinematics& k = *kin_est_;
  sole_[0] = k.left_sole();
  sole_[1] = k.right_sole();
  for (int i = 0; i < 2; ++i) {
    force_[i] = k.soles()[sole_[i]].force_sensor;
    sensor_site_[i] = k.robot().forces[force_[i]].site_id;
  }
  imu_ = options_.estimator.imu;
  if (imu_ < 0 || imu_ >= static_cast<int>(k.robot().imus.size())) {
    return ConfigStatus::Fail(ConfigError::kOption, "the robot has no IMU " + std::to_string(imu_));
  }
  try {
    estimator_ = std::make_unique<model::BaseEstimator>(kin_est_.get(), options_.estimator);
    for (int i = 0; i < 2; ++i) {
      leg_ik_[i] = std::make_unique<model::LimbIk>(
          model::LimbIk::ForSole(*kin_ik_, k.robot().base_body, sole_[i]));
    }
  } catch (const std::exception& e) {
    return ConfigStatus::Fail(ConfigError::kMismatch, e.what());
  }

  // the torso joints for the hip strategy, and the upper body's inertia about them
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(target_.data());
  kin_ik_->Update();
  const int imu_body = k.m()->site_bodyid[k.robot().imus[imu_].site_id];
  const std::vector<int> torso = k.Chain(k.robot().base_body, imu_body);
  torso_pitch_joint_ = FindTorsoJoint(*kin_ik_, torso, Eigen::Vector3d::UnitY());
  torso_roll_joint_ = FindTorsoJoint(*kin_ik_, torso, Eigen::Vector3d::UnitX());
  StabilizerGains& g = stabilizer_.gains();
  if (torso_pitch_joint_ < 0 && torso_roll_joint_ < 0) {
    g.hip_strategy = false;  // no torso joint: ankle strategy only (reported)
  } else {
    const int j = torso_pitch_joint_ >= 0 ? torso_pitch_joint_ : torso_roll_joint_;
    Eigen::MatrixXd M(kin_ik_->nv(), kin_ik_->nv());
    kin_ik_->MassMatrix(M);
    const int col = kin_ik_->base_columns() + j;
    const int dof = k.robot().joints[j].dof_adr;
    // the link inertia about the joint, without the rotor (its reaction goes to the base)
    g.torso_inertia = std::max(M(col, col) - k.m()->dof_armature[dof], 1e-3);
  }
  // nominal soles in the base frame at the stance pose, and the CoM shift that puts the CoM
  // over their middle (the base moves by it; the feet, a few % of the mass, stay)
  for (int i = 0; i < 2; ++i) {
    p_BS_nominal_[i] = kin_ik_->p_WSole(sole_[i]);
    R_BS_nominal_[i] = kin_ik_->R_WSole(sole_[i]);
  }
  // the stance plan: centred, then on each sole asked for
  StanceShift centre, side[2];
  if (options_.centre_com &&
      !SolveShiftOver(0.5 * (p_BS_nominal_[0] + p_BS_nominal_[1]).head<2>(), &centre)) {
    return ConfigStatus::Fail(ConfigError::kLimits,
                              "the legs cannot move the CoM over the middle of the soles from "
                              "this stance pose (use --no-centre-com)");
  }
  for (int side_i : options_.one_leg.sides) {
    if (side_i != 0 && side_i != 1) {
      return ConfigStatus::Fail(ConfigError::kOption, "--one-leg takes left or right");
    }
    if (!SolveShiftOver(p_BS_nominal_[side_i].head<2>(), &side[side_i])) {
      return ConfigStatus::Fail(ConfigError::kLimits,
                                std::string("the legs cannot move the CoM over the ") +
                                    (side_i == 0 ? "left" : "right") + " sole from this stance pose");
    }
  }
  plan_.Configure(centre, options_.centre_com ? options_.centre_time : 0.0, side, options_.one_leg);
  return ConfigStatus::Ok();
}

bool BalanceController::SolveShiftOver(const Eigen::Vector2d& p_B, StanceShift* shift) {
  // the legs move with the feet, so the hips must move further than the CoM: fixed-point
  // iterations of leg IK with the soles held where they are
  for (int j = 0; j < njoint(); ++j) q_ik_[j] = target_[j];
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(q_ik_.data());
  kin_ik_->Update();
  const Eigen::Vector2d c0 = kin_ik_->p_WCoM().head<2>();
  Eigen::Vector2d hips = Eigen::Vector2d::Zero();
  for (int it = 0; it < 12; ++it) {
    for (int i = 0; i < 2; ++i) {
      const Eigen::Vector3d p = p_BS_nominal_[i] - Eigen::Vector3d(hips.x(), hips.y(), 0);
      if (leg_ik_[i]->Solve(*kin_ik_, p, R_BS_nominal_[i], q_ik_.data()).status !=
          model::IkStatus::kConverged)
        return false;
    }
    kin_ik_->Update();
    // the CoM relative to the target point, which moved by -hips in the base frame
    const Eigen::Vector2d rel = kin_ik_->p_WCoM().head<2>() - (p_B - hips);
    hips -= rel;
    if (rel.norm() < 1e-5) break;
  }
  shift->hips = hips;
  shift->com = p_B - c0;
  return true;
}

void BalanceController::on_activate(const shm::SensorBlock& s) noexcept {
  for (int j = 0; j < njoint(); ++j) {
    start_[j] = std::isfinite(s.q[j]) ? s.q[j] : target_[j];
    q_ref_[j] = q_prev_[j] = start_[j];
    dq_ref_[j] = 0;
  }
  start_time_ = last_time_ = activate_time_ = s.time;
  phase_ = Phase::kRamp;
  stabilizer_.Reset();
  for (int j = 0; j < njoint(); ++j) ramp_target_[j] = target_[j];
  HoldReason why;
  if (!SensorsUsable(s, &why) || !estimator_->Reset(s)) {
    phase_ = Phase::kHold;
    stats_.hold_reason = SensorsUsable(s, &why) ? HoldReason::kEstimatorFailed : why;
    stats_.hold_time = s.time;
    return;
  }
  ramp_started_ = false;
}

void BalanceController::StartRamp(double time) noexcept {
  ramp_started_ = true;
  start_time_ = time;
  // the stance pose with each loaded sole kept at the tilt it stands on
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(ramp_target_.data());
  kin_ik_->UpdatePositions();
  const model::BaseEstimate& e = estimator_->estimate();
  for (int i = 0; i < 2; ++i) {
    if (!e.contact[i]) continue;
    const Eigen::Vector2d tilt = SoleTilt(i).cwiseMax(-options_.gains.max_foot_rotation)
                                     .cwiseMin(options_.gains.max_foot_rotation);
    const Eigen::Matrix3d R = Rx(tilt.x()) * Ry(tilt.y()) * R_BS_nominal_[i];
    std::array<double, shm::kMaxJoints> trial = ramp_target_;
    if (leg_ik_[i]->Solve(*kin_ik_, p_BS_nominal_[i], R, trial.data()).status ==
        model::IkStatus::kConverged) {
      for (int j : leg_ik_[i]->chain()) ramp_target_[j] = trial[j];
    }
  }
}

Eigen::Vector2d BalanceController::SoleTilt(int i) const {
  const model::Kinematics& k = *kin_est_;
  const Eigen::Vector3d x_W = estimator_->estimate().quat_WB * Eigen::Vector3d::UnitX();
  const double yaw = std::atan2(x_W.y(), x_W.x());
  const Eigen::Vector3d n = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()) *
                            (k.R_WSole(sole_[i]) * Eigen::Vector3d::UnitZ());
  return Eigen::Vector2d(std::atan2(-n.y(), n.z()), std::asin(std::clamp(n.x(), -1.0, 1.0)));
}

//---------------- the cycle ----------------

bool BalanceController::SensorsUsable(const shm::SensorBlock& s, HoldReason* why) const noexcept {
  if (s.status & shm::status::kBoardFault) {
    *why = HoldReason::kBoardFault;
    return false;
  }
  bool ok = true;
  for (int j = 0; j < njoint(); ++j) ok = ok && std::isfinite(s.q[j]) && std::isfinite(s.dq[j]);
  for (int i = 0; i < 2; ++i) {
    const shm::ForceTorque& ft = s.force[force_[i]];
    for (int k = 0; k < 3; ++k) ok = ok && std::isfinite(ft.force[k]) && std::isfinite(ft.torque[k]);
  }
  const shm::Imu& imu = s.imu[imu_];
  for (int k = 0; k < 3; ++k) ok = ok && std::isfinite(imu.gyro[k]) && std::isfinite(imu.accel[k]);
  if (!ok) *why = HoldReason::kNonFiniteSensors;
  return ok;
}

void BalanceController::EnterStand(const shm::SensorBlock& s) noexcept {
  const model::BaseEstimate& e = estimator_->estimate();
  c_ref_start_ = c_ref_ = e.p_WCoM.head<2>();
  stand_time_ = s.time;
  const Eigen::Vector2d tilt[2] = {SoleTilt(0), SoleTilt(1)};
  stabilizer_.Reset(tilt);
  for (int j = 0; j < njoint(); ++j) q_ik_[j] = ramp_target_[j];
  phase_ = Phase::kStand;
}

void BalanceController::Stand(const shm::SensorBlock& s, double dt) noexcept {
  const model::Kinematics& k = *kin_est_;  // at the estimated state
  const model::BaseEstimate& e = estimator_->estimate();

  // the plan's targets now, c_ref moving with the CoM shift (yaw of the base applied)
  targets_ = plan_.At(s.time - stand_time_);
  const StanceTargets& plan = targets_;
  const Eigen::Vector3d x_W = e.quat_WB * Eigen::Vector3d::UnitX();
  const double yaw = std::atan2(x_W.y(), x_W.x());
  const Eigen::Rotation2Dd R_yaw(yaw);
  c_ref_ = c_ref_start_ + R_yaw * plan.shift.com;
  // its velocity and acceleration, by central differences of the plan
  constexpr double h = 0.01;  // [s]
  const double t = s.time - stand_time_;
  const Eigen::Vector2d c_m = plan_.At(t - h).shift.com, c_p = plan_.At(t + h).shift.com;
  input_.dc_ref = R_yaw * ((c_p - c_m) / (2 * h));
  input_.ddc_ref = R_yaw * ((c_p - 2 * plan.shift.com + c_m) / (h * h));

  // the stabilizer's inputs: CoM, ankle wrenches in W, the support
  input_.c = e.p_WCoM;
  input_.dc = e.v_WCoM;
  input_.c_ref = c_ref_;
  input_.mass = k.mass();
  double ground = 0;
  for (int i = 0; i < 2; ++i) {
    const shm::ForceTorque& ft = s.force[force_[i]];
    const Eigen::Matrix3d R_WS = k.R_WSite(sensor_site_[i]);
    FootWrench& w = input_.feet[i];
    w.p_WS = k.p_WSite(sensor_site_[i]);
    w.f_W = R_WS * Eigen::Vector3d(ft.force[0], ft.force[1], ft.force[2]);
    w.n_W = R_WS * Eigen::Vector3d(ft.torque[0], ft.torque[1], ft.torque[2]);
    const model::SoleMap& sole = k.soles()[sole_[i]];
    input_.sole_tilt[i] = SoleTilt(i);
    const Eigen::Vector3d p = k.p_WSole(sole_[i]);
    input_.support.centre[i] = p.head<2>();
    input_.support.half_size[i] = Eigen::Vector2d(sole.half_size[0], sole.half_size[1]);
    ground += 0.5 * p.z();
  }
  for (int i = 0; i < 2; ++i) input_.support.supporting[i] = plan.supporting[i];
  // the swing foot's lift, measured (estimate) against the plan: the stance leg and hip yield
  // under the whole weight, so the commanded lift is topped up by a slow integral
  double lift_cmd[2] = {plan.lift[0], plan.lift[1]};
  constexpr double kLiftGain = 5.0;        // [1/s]
  constexpr double kMaxLiftExtra = 0.03;   // [m]
  constexpr double kLiftExtraDecay = 0.5;  // [s] once the foot is down again
  if (plan.standing_on < 0) {
    // back on both feet: what was added goes away slowly (the dz control takes over)
    lift_extra_ -= dt * lift_extra_ / kLiftExtraDecay;
    lift_cmd[last_swing_] += lift_extra_;
    lifted_ = false;
    if (lift_extra_ < 1e-4)
      for (int i = 0; i < 2; ++i) sole_z0_[i] = k.p_WSole(sole_[i]).z();
  } else {
    const int sw = 1 - plan.standing_on;
    last_swing_ = sw;
    const double measured = k.p_WSole(sole_[sw]).z() - sole_z0_[sw];
    const double full = options_.one_leg.lift > 0 ? plan.lift[sw] / options_.one_leg.lift : 0.0;
    if (full > 0.999) lifted_ = true;
    // while rising, the extra grows with the lift; once up, it stays with the foot through the
    // lowering, so that the foot meets the ground with the lift's zero speed, not early
    if (full > 0.2 && !(lifted_ && full < 0.999))
      lift_extra_ += dt * kLiftGain * (plan.lift[sw] - measured);
    lift_extra_ = std::clamp(lift_extra_, 0.0, kMaxLiftExtra);
    lift_cmd[sw] += (lifted_ ? 1.0 : full) * lift_extra_;
  }
  if (plan.standing_on >= 0) ground = k.p_WSole(sole_[plan.standing_on]).z();
  input_.support.ground_z = ground;
  const StabilizerOutput& out = stabilizer_.Update(input_, dt);

  // statistics
  ++stats_.stand_cycles;
  if (out.zmp_valid)
    stats_.max_zmp_error = std::max(stats_.max_zmp_error, (out.zmp_measured - out.zmp_desired).norm());
  stats_.max_dcm_error = std::max(stats_.max_dcm_error, (out.dcm - c_ref_).norm());
  stats_.max_torso_angle =
      std::max({stats_.max_torso_angle, std::abs(out.torso_pitch), std::abs(out.torso_roll)});
  for (int i = 0; i < 2; ++i) {
    stats_.max_foot_rotation = std::max(
        {stats_.max_foot_rotation, std::abs(out.foot_roll[i]), std::abs(out.foot_pitch[i])});
  }

  // joint references: stance pose, torso offsets, legs by IK to the offset soles
  for (int j = 0; j < njoint(); ++j) q_ik_[j] = std::isfinite(q_ik_[j]) ? q_ik_[j] : ramp_target_[j];
  if (torso_pitch_joint_ >= 0) q_ik_[torso_pitch_joint_] = target_[torso_pitch_joint_] + out.torso_pitch;
  if (torso_roll_joint_ >= 0) q_ik_[torso_roll_joint_] = target_[torso_roll_joint_] + out.torso_roll;
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(q_ik_.data());
  kin_ik_->UpdatePositions();
  const Eigen::Vector2d hips_B = plan.shift.hips + R_yaw.inverse() * out.com_offset;
  for (int i = 0; i < 2; ++i) {
    const double side = i == 0 ? 0.5 : -0.5;
    const Eigen::Vector3d p =
        p_BS_nominal_[i] + Eigen::Vector3d(-hips_B.x(), -hips_B.y(), side * out.dz + lift_cmd[i]);
    const Eigen::Matrix3d R = Rx(out.foot_roll[i]) * Ry(out.foot_pitch[i]) * R_BS_nominal_[i];
    std::array<double, shm::kMaxJoints> trial = q_ik_;
    const model::IkResult r = leg_ik_[i]->Solve(*kin_ik_, p, R, trial.data());
    if (r.status == model::IkStatus::kConverged) {
      for (int j : leg_ik_[i]->chain()) q_ik_[j] = trial[j];
    } else {
      ++stats_.ik_failures;
    }
  }
  for (int j = 0; j < njoint(); ++j) q_ref_[j] = q_ik_[j];
}

void BalanceController::Write(shm::CommandBlock* commands, double dt) noexcept {
  const shm::SegmentHeader& h = header();
  for (int j = 0; j < njoint(); ++j) {
    shm::JointCommand& c = commands->joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q_ref_[j];
    c.dq_ref = dq_ref_[j];
    c.tau_ff = 0;
    c.kp = h.default_kp[j];
    c.kd = h.default_kd[j];
  }
  (void)dt;
}

void BalanceController::on_update(const shm::SensorBlock& s, shm::CommandBlock* commands) noexcept {
  double dt = s.time - last_time_;
  // a block whose time does not advance is stale (the producer republished old data); the
  // activation block comes twice (activate, then the first update)
  const bool stale = !(dt > 0) && s.time != activate_time_;
  HoldReason why = stale ? HoldReason::kStaleSensors : HoldReason::kNone;
  if (!(dt > 0) || !std::isfinite(dt)) dt = header().control_period;
  last_time_ = s.time;
  for (int j = 0; j < njoint(); ++j) q_prev_[j] = q_ref_[j];

  if (phase_ != Phase::kHold && (why != HoldReason::kNone || !SensorsUsable(s, &why) ||
                                 !estimator_->Update(s, dt))) {
    phase_ = Phase::kHold;
    stats_.hold_reason = why == HoldReason::kNone ? HoldReason::kEstimatorFailed : why;
    stats_.hold_time = s.time;
  }
  switch (phase_) {
    case Phase::kRamp: {
      // the ramp starts once both soles are on the ground (their tilt is the ground's then) and
      // the estimator has settled (its tilt from one accelerometer sample at Reset is not
      // trusted), or after kMaxWaitForContact
      if (!ramp_started_) {
        const model::BaseEstimate& e = estimator_->estimate();
        const double waited = s.time - activate_time_;
        if ((e.contact[0] && e.contact[1] && waited >= kEstimatorSettle) ||
            waited > kMaxWaitForContact)
          StartRamp(s.time);
        break;  // q_ref_ holds the measured start pose
      }
      const double elapsed = s.time - start_time_;
      SampleRamp(start_.data(), ramp_target_.data(), njoint(), elapsed, options_.ramp, q_ref_.data(),
                 dq_ref_.data());
      if (elapsed >= options_.ramp + options_.settle) EnterStand(s);
      break;
    }
    case Phase::kStand:
      Stand(s, dt);
      for (int j = 0; j < njoint(); ++j) dq_ref_[j] = 0;
      break;
    case Phase::kHold:
      ++stats_.hold_cycles;
      for (int j = 0; j < njoint(); ++j) dq_ref_[j] = 0;  // q_ref_ stays: the last commanded
      break;
  }
  Write(commands, dt);
}

//---------------- report ----------------

void BalanceController::report(std::ostream& out) const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "balance: stood %.2f s (%llu cycles); max |ZMP error| %.1f mm, max |DCM - c_ref| "
                "%.1f mm, max foot rotation %.2f deg, max torso offset %.2f deg%s; %llu leg IK "
                "results not converged\n",
                stats_.stand_cycles * header().control_period,
                static_cast<unsigned long long>(stats_.stand_cycles), stats_.max_zmp_error * 1e3,
                stats_.max_dcm_error * 1e3, stats_.max_foot_rotation * 180 / M_PI,
                stats_.max_torso_angle * 180 / M_PI,
                stabilizer_.gains().hip_strategy ? "" : " (hip strategy off)",
                static_cast<unsigned long long>(stats_.ik_failures));
  out << buf;
  if (stats_.hold_reason != HoldReason::kNone) {
    std::snprintf(buf, sizeof buf,
                  "balance: HELD the last commanded posture from t = %.3f s (%llu cycles): %s; "
                  "no command after that used the sensors\n",
                  stats_.hold_time, static_cast<unsigned long long>(stats_.hold_cycles),
                  HoldReasonName(stats_.hold_reason));
    out << buf;
  }
}

}  // namespace ohrp::controllers
