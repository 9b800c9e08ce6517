// The balance controller: activation, the cycle (ramp, stance, hold) and the report (see
// balance.h; its set-up is in balance_setup.cc).
#include "controllers/balance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "controllers/ramp.h"

namespace ohrp::controllers {
namespace {

constexpr double kMaxWaitForContact = 1.0;  // [s] before the ramp starts without both soles down
constexpr double kEstimatorSettle = 0.3;    // [s] of estimation before the soles' tilt is trusted
constexpr int kStaleBlocks = 1;             // blocks in a row with the same time: stale sensors

Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }

}  // namespace

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
    const Eigen::Vector2d tilt = SoleTilt(i).cwiseMax(-options_.gains.max_ground_tilt)
                                     .cwiseMin(options_.gains.max_ground_tilt);
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
  const model::BaseEstimate& e = estimator_->estimate();
  const Eigen::Vector3d x_W = e.quat_WB * Eigen::Vector3d::UnitX();
  const Eigen::Rotation2Dd R_yaw(std::atan2(x_W.y(), x_W.x()));
  targets_ = plan_.At(s.time - stand_time_);
  FillStabilizerInput(s, s.time - stand_time_, R_yaw);
  double lift[2];
  SwingLift(dt, lift);
  const StabilizerOutput& out = stabilizer_.Update(input_, dt);
  CountStand(out);
  SolveJoints(out, R_yaw.inverse() * out.com_offset, lift);
  for (int j = 0; j < njoint(); ++j) dq_ref_[j] = 0;
  CarryLoad(out);
}

void BalanceController::CarryLoad(const StabilizerOutput& out) noexcept {
  if (load_ff_)
    load_ff_->Compute(*kin_est_, out.fz_share, header().tau_max, tau_ff_.data());
  else
    tau_ff_.fill(0.0);
}

void BalanceController::FillStabilizerInput(const shm::SensorBlock& s, double t,
                                            const Eigen::Rotation2Dd& R_yaw) noexcept {
  const model::Kinematics& k = *kin_est_;  // at the estimated state
  const model::BaseEstimate& e = estimator_->estimate();
  const StanceTargets& plan = targets_;

  // c_ref moves with the plan's CoM shift (yaw of the base applied); its velocity and
  // acceleration by central differences of the plan
  constexpr double h = 0.01;  // [s]
  c_ref_ = c_ref_start_ + R_yaw * plan.shift.com;
  const Eigen::Vector2d c_m = plan_.At(t - h).shift.com, c_p = plan_.At(t + h).shift.com;
  input_.c_ref = c_ref_;
  input_.dc_ref = R_yaw * ((c_p - c_m) / (2 * h));
  input_.ddc_ref = R_yaw * ((c_p - 2 * plan.shift.com + c_m) / (h * h));
  input_.c = e.p_WCoM;
  input_.dc = e.v_WCoM;
  input_.mass = k.mass();
  input_.heading = R_yaw.angle();

  // the ankle wrenches in W, the soles' tilt and the support
  double ground = 0;
  for (int i = 0; i < 2; ++i) {
    const shm::ForceTorque& ft = s.force[force_[i]];
    const Eigen::Matrix3d R_WS = k.R_WSite(sensor_site_[i]);
    FootWrench& w = input_.feet[i];
    w.p_WS = k.p_WSite(sensor_site_[i]);
    w.f_W = R_WS * Eigen::Vector3d(ft.force[0], ft.force[1], ft.force[2]);
    w.n_W = R_WS * Eigen::Vector3d(ft.torque[0], ft.torque[1], ft.torque[2]);
    input_.sole_tilt[i] = SoleTilt(i);
    const model::SoleMap& sole = k.soles()[sole_[i]];
    const Eigen::Vector3d p = k.p_WSole(sole_[i]);
    input_.support.centre[i] = p.head<2>();
    input_.support.half_size[i] = Eigen::Vector2d(sole.half_size[0], sole.half_size[1]);
    input_.support.supporting[i] = plan.supporting[i];
    ground += 0.5 * p.z();
  }
  if (plan.standing_on >= 0) ground = k.p_WSole(sole_[plan.standing_on]).z();
  input_.support.ground_z = ground;
}

void BalanceController::SwingLift(double dt, double lift[2]) noexcept {
  // the swing foot's lift, measured (estimate) against the plan: the stance leg and hip yield
  // under the whole weight, so the commanded lift is topped up by a slow integral
  constexpr double kLiftGain = 5.0;        // [1/s]
  constexpr double kMaxLiftExtra = 0.03;   // [m]
  constexpr double kLiftExtraDecay = 0.5;  // [s] once the foot is down again
  const model::Kinematics& k = *kin_est_;
  const StanceTargets& plan = targets_;
  lift[0] = plan.lift[0];
  lift[1] = plan.lift[1];
  if (plan.standing_on < 0) {
    // back on both feet: what was added goes away slowly (the dz control takes over)
    lift_extra_ -= dt * lift_extra_ / kLiftExtraDecay;
    lift[last_swing_] += lift_extra_;
    lifted_ = false;
    if (lift_extra_ < 1e-4)
      for (int i = 0; i < 2; ++i) sole_z0_[i] = k.p_WSole(sole_[i]).z();
    return;
  }
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
  lift[sw] += (lifted_ ? 1.0 : full) * lift_extra_;
}

void BalanceController::CountStand(const StabilizerOutput& out) noexcept {
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
}

void BalanceController::SolveJoints(const StabilizerOutput& out, const Eigen::Vector2d& offset_B,
                                    const double lift[2]) noexcept {
  // the stance pose, the torso offsets, the legs by IK to the soles' targets in the base frame
  // (upright): the hips shifted by the plan and the CoM correction, the soles rotated by the
  // foot offsets and raised by the height control and the lift
  for (int j = 0; j < njoint(); ++j) q_ik_[j] = std::isfinite(q_ik_[j]) ? q_ik_[j] : ramp_target_[j];
  if (torso_pitch_joint_ >= 0) q_ik_[torso_pitch_joint_] = target_[torso_pitch_joint_] + out.torso_pitch;
  if (torso_roll_joint_ >= 0) q_ik_[torso_roll_joint_] = target_[torso_roll_joint_] + out.torso_roll;
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(q_ik_.data());
  kin_ik_->UpdatePositions();
  const Eigen::Vector2d hips_B = targets_.shift.hips + offset_B;
  bool failed = false;
  for (int i = 0; i < 2; ++i) {
    const double side = i == 0 ? 0.5 : -0.5;
    const Eigen::Vector3d p =
        p_BS_nominal_[i] + Eigen::Vector3d(-hips_B.x(), -hips_B.y(), side * out.dz + lift[i]);
    const Eigen::Matrix3d R = Rx(out.foot_roll[i]) * Ry(out.foot_pitch[i]) * R_BS_nominal_[i];
    std::array<double, shm::kMaxJoints> trial = q_ik_;
    const model::IkResult r = leg_ik_[i]->Solve(*kin_ik_, p, R, trial.data());
    if (r.status == model::IkStatus::kConverged) {
      for (int j : leg_ik_[i]->chain()) q_ik_[j] = trial[j];
    } else {
      ++stats_.ik_failures;
      failed = true;
    }
  }
  CountIk(failed);
  for (int j = 0; j < njoint(); ++j) q_ref_[j] = q_ik_[j];
}

void BalanceController::CountIk(bool failed) noexcept {
  ik_fail_run_ = failed ? ik_fail_run_ + 1 : 0;
  if (failed) ++stats_.ik_failed_cycles;
  stats_.longest_ik_failure =
      std::max(stats_.longest_ik_failure, ik_fail_run_ * header().control_period);
}

void BalanceController::Write(shm::CommandBlock* commands, double dt) noexcept {
  const shm::SegmentHeader& h = header();
  // the suggested gains close at 6 Hz (robot_model/model.cc)
  const double scale = options_.servo_frequency > 0 ? options_.servo_frequency / 6.0 : 1.0;
  for (int j = 0; j < njoint(); ++j) {
    shm::JointCommand& c = commands->joint[j];
    c.mode = shm::JointMode::kPosition;
    c.q_ref = q_ref_[j];
    c.dq_ref = dq_ref_[j];
    c.tau_ff = tau_ff_[j];
    c.kp = h.default_kp[j] * scale * scale;
    c.kd = h.default_kd[j] * scale;
  }
  (void)dt;
}

void BalanceController::on_update(const shm::SensorBlock& s, shm::CommandBlock* commands) noexcept {
  double dt = s.time - last_time_;
  // blocks whose time does not advance are stale (the producer republishes old data); the
  // activation block comes twice (activate, then the first update), and a producer's last
  // block (shutting down) may repeat its time once
  stale_blocks_ = (dt > 0 || s.time == activate_time_) ? 0 : stale_blocks_ + 1;
  const bool stale =
      stale_blocks_ >= kStaleBlocks && !(s.status & shm::status::kShuttingDown);
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
      break;
    case Phase::kHold:
      ++stats_.hold_cycles;
      for (int j = 0; j < njoint(); ++j) dq_ref_[j] = 0;  // q_ref_ stays: the last commanded
      break;
  }
  Write(commands, dt);
}

//---------------- the fall watch and the verdict ----------------

void BalanceController::fall_limits(FallLimits* limits) const {
  *limits = FallLimitsFor(com_height_, sole_reach_, 0.0);  // the base's tilt: no torso in it
  limits->feet[0] = force_[0];
  limits->feet[1] = force_[1];
  limits->imu = imu_;
}

double BalanceController::base_tilt() const noexcept {
  if (phase_ == Phase::kHold || !estimator_) return kNoTilt;
  const Eigen::Vector3d z = estimator_->estimate().quat_WB * Eigen::Vector3d::UnitZ();
  return std::isfinite(z.z()) ? std::acos(std::clamp(z.z(), -1.0, 1.0)) : kNoTilt;
}

double BalanceController::com_height() const noexcept {
  if (phase_ == Phase::kHold || !estimator_) return kNoTilt;
  const model::Kinematics& k = *kin_est_;  // at the estimated state
  const double h = estimator_->estimate().p_WCoM.z() -
                   std::min(k.p_WSole(sole_[0]).z(), k.p_WSole(sole_[1]).z());
  return std::isfinite(h) ? h : kNoTilt;
}

std::string BalanceController::failure() const {
  // persistent: the legs missed their targets for longer than the robot's pendulum time (the
  // stance was not under control for that long), or in more than a tenth of the stance
  const double tau = std::sqrt(std::max(com_height_, 1e-3) / 9.81);
  const bool long_run = stats_.longest_ik_failure > tau;
  const bool many = stats_.stand_cycles > 0 && stats_.ik_failed_cycles * 10 > stats_.stand_cycles;
  if (!long_run && !many) return std::string();
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "the legs' inverse kinematics failed persistently: in %llu of %llu stance "
                "cycles, for up to %.2f s in a row (limits: a tenth of the stance, or the "
                "pendulum time %.2f s): the robot did not hold the stance commanded",
                static_cast<unsigned long long>(stats_.ik_failed_cycles),
                static_cast<unsigned long long>(stats_.stand_cycles), stats_.longest_ik_failure,
                tau);
  return buf;
}

//---------------- report ----------------

std::string BalanceController::StanceFigures() const {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%.2f s (%llu cycles); max |ZMP error| %.1f mm, max |DCM - c_ref| %.1f mm, max "
                "foot rotation %.2f deg, max torso offset %.2f deg%s; %llu leg IK results not "
                "converged",
                stats_.stand_cycles * header().control_period,
                static_cast<unsigned long long>(stats_.stand_cycles), stats_.max_zmp_error * 1e3,
                stats_.max_dcm_error * 1e3, stats_.max_foot_rotation * 180 / M_PI,
                stats_.max_torso_angle * 180 / M_PI,
                stabilizer_.gains().hip_strategy ? "" : " (hip strategy off)",
                static_cast<unsigned long long>(stats_.ik_failures));
  return buf;
}

void BalanceController::report(std::ostream& out) const {
  char buf[512];
  const std::string failed = BalanceController::failure();  // the stance's own, not a subclass's
  if (fall().cause != FallCause::kNone) {
    out << "balance: did NOT keep the robot standing: it fell (" << FallCauseName(fall().cause)
        << ", t = " << fall().time << " s); in stance before that " << StanceFigures() << "\n";
  } else if (!failed.empty()) {
    out << "balance: did NOT stand as commanded (leg IK failing persistently); in stance "
        << StanceFigures() << "\n";
  } else {
    out << "balance: stood " << StanceFigures() << "\n";
  }
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
