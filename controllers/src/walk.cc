// The walk controller's cycle: the switch from standing, the stabilizer and the legs (see
// walk.h; commands and the plan frame in walk_plan.cc, set-up in walk_setup.cc, log and report
// in walk_report.cc).
#include "controllers/walk.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <limits>
#include <cstdio>
#include <ostream>

#include "walk_geometry.h"

namespace ohrp::controllers {
namespace {

// the producer's suggested gains close at this frequency on each joint's own inertia
// (robot_model/model.cc): that inertia is default_kp / (2 pi f)^2
constexpr double kSuggestedServoHz = 6.0;

volatile std::sig_atomic_t g_walk_stop = 0;

}  // namespace

using walk_geometry::Rx;
using walk_geometry::Ry;
using walk_geometry::Rz;
using walk_geometry::Wrap;
using walk_geometry::YawOf;

void WalkController::RequestWalkStop() noexcept { g_walk_stop = 1; }

double WalkController::base_tilt() const noexcept {
  const double tilt = BalanceController::base_tilt();
  if (!started_ || roll_ == 0 || !std::isfinite(tilt)) return tilt;
  const Eigen::Matrix3d R = estimator_->estimate().quat_WB.toRotationMatrix();
  const Eigen::Vector3d want = Rz(YawOf(R)) * Rx(roll_) * Eigen::Vector3d::UnitZ();
  const double c = (R * Eigen::Vector3d::UnitZ()).dot(want);
  return std::isfinite(c) ? std::acos(std::clamp(c, -1.0, 1.0)) : tilt;
}

const char* WalkController::tilt_reference() const noexcept {
  return started_ && roll_ != 0 ? "its commanded orientation (the pelvis rolled on purpose)"
                                : "upright";
}

bool WalkController::done() const {
  return started_ && !gen_.walking() && next_command_ >= static_cast<int>(chunks_plan_.size());
}

void WalkController::Stand(const shm::SensorBlock& s, double dt) noexcept {
  if (!started_) {
    BalanceController::Stand(s, dt);
    if (s.time - stand_time_ >= plan_.duration()) StartWalking(s);
    return;
  }
  WalkCycle(s, dt);
}

//---------------- the start ----------------

void WalkController::StartWalking(const shm::SensorBlock& s) noexcept {
  // the commanded stance in the base frame (upright, at the origin)
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(q_ik_.data());
  kin_ik_->Update();
  Eigen::Vector3d S_B[2];
  for (int i = 0; i < 2; ++i) S_B[i] = kin_ik_->p_WSole(sole_[i]);
  const Eigen::Vector3d c_B = kin_ik_->p_WCoM();
  const Eigen::Vector3d mid_B = 0.5 * (S_B[0] + S_B[1]);
  // placed on the estimated soles' middle and heading, the ground at z = 0
  const model::Kinematics& k = *kin_est_;
  Eigen::Vector3d mid_est = Eigen::Vector3d::Zero();
  double yaw_est[2];
  for (int i = 0; i < 2; ++i) {
    mid_est += 0.5 * k.p_WSole(sole_[i]);
    yaw_est[i] = YawOf(k.R_WSole(sole_[i])) - sole_yaw_B_[i];
  }
  const double yaw = yaw_est[0] + 0.5 * Wrap(yaw_est[1] - yaw_est[0]);
  const Eigen::Matrix3d R = Rz(yaw);
  walking::FeetPose feet;
  for (int i = 0; i < 2; ++i) {
    feet.p[i] = R * (S_B[i] - mid_B);
    feet.p[i] += Eigen::Vector3d(mid_est.x(), mid_est.y(), 0);
    feet.p[i].z() = 0;
    feet.yaw[i] = Wrap(yaw + sole_yaw_B_[i]);
  }
  // the commanded stance holds the stabilizer's CoM correction as a shift of the hips; the walk
  // adds it to the planned CoM, so the plan starts without it
  const Eigen::Vector2d offset = stabilizer_.output().com_offset;
  Eigen::Vector3d com = R * (c_B - mid_B) + Eigen::Vector3d(mid_est.x() - offset.x(),
                                                            mid_est.y() - offset.y(), 0);
  com.z() = c_B.z() - mid_B.z();
  p_WB_ = R * (-mid_B) + Eigen::Vector3d(mid_est.x(), mid_est.y(), 0);
  p_WB_.z() = -mid_B.z();
  p_WB_plan_ = p_WB_;
  roll_ = roll_plan_ = 0;
  plan_valid_ = false;
  // the generator walks at its configured height; the lowering is made by the controller
  z_lower_ = com.z() - gen_.zc();
  com.z() = gen_.zc();
  std::string error;  // no allocation: zc is the configured one, the gains stay
  gen_.Start(s.time, feet, com, &error);
  // the commands' steps into the plan frame: the nominal stance's mid frame onto this one
  const Eigen::Vector3d mid_plan = 0.5 * (feet.p[0] + feet.p[1]);
  for (size_t c = 0; c < chunks_.size(); ++c) {
    for (size_t n = 0; n < chunks_[c].size(); ++n) {
      walking::Footstep& f = chunks_plan_[c][n];
      f = chunks_[c][n];
      f.p = R * f.p + mid_plan;
      f.yaw = Wrap(f.yaw + yaw);
    }
  }
  started_ = true;
  // on a known terrain the soles land at the tilt the plan gives them: their rest orientation is
  // that, not what the (drifting) tilt estimate says
  if (terrain_) stabilizer_.gains().ground_adaptation = 0;
  walk_t0_ = ready_time_ = s.time;
  next_command_ = 0;
  walk_stats_.walk_start = s.time;
  chunk_ = -1;
  recovery_shift_.setZero();
  UpdateFrame(0, true);
  frame0_p_ = frame_p_;
  frame0_yaw_ = frame_yaw_;
}

//---------------- the cycle ----------------

void WalkController::WalkCycle(const shm::SensorBlock& s, double dt) noexcept {
  if (g_walk_stop) {
    g_walk_stop = 0;
    Stop();
  }
  NextCommand(s.time);
  LiveCycle();
  UpdateFrame(dt, false);
  Remap();
  AdjustStep();
  const walking::WalkSample& w = gen_.Advance();
  ++walk_stats_.walk_cycles;
  Touchdown(s, w, dt);
  FillWalkInput(s, w);
  // a swing foot turns to the tilt of the surface it will land on (the plan's); once down, the
  // stabilizer carries on from there
  if (w.gait.swing >= 0)
    stabilizer_.SetFootTilt(w.gait.swing, w.gait.feet.roll[w.gait.swing], w.gait.feet.pitch[w.gait.swing]);
  const StabilizerOutput& out = stabilizer_.Update(input_, dt);
  CountStand(out);
  walk_stats_.max_com_error =
      std::max(walk_stats_.max_com_error, (input_.c.head<2>() - w.com.head<2>()).norm());
  if (out.zmp_valid)
    walk_stats_.max_zmp_error =
        std::max(walk_stats_.max_zmp_error, (out.zmp_measured - out.zmp_desired).norm());
  double lowered, unused_rate, unused_acceleration;
  walking::MinJerk((s.time - walk_t0_) / walk_options_.lower_time, &lowered, &unused_rate,
                   &unused_acceleration);
  SolveWalkJoints(out, w, z_lower_ * (1.0 - lowered) + com_dz_);
  // velocity references and feed-forward from the plan alone (the stabilizer's corrections
  // carry force feedback: differentiated, they would close a derivative loop through the
  // contact): the legs' rates of the plan's IK; for the swing leg (in the air, where the servo
  // alone lags) also the torque that accelerates each joint's own inertia along the plan (the
  // rotors' reflected inertia dominates it on geared robots)
  const shm::SegmentHeader& h = header();
  const double w2 = std::pow(2 * M_PI * kSuggestedServoHz, 2);
  CarryLoad(out);  // the load's feed-forward; the swing leg's inertia on top
  for (int j = 0; j < njoint(); ++j) dq_ref_[j] = 0;
  for (int i = 0; i < 2; ++i) {
    for (int j : leg_ik_[i]->chain()) {
      const double dq = plan_valid_ ? (q_plan_[j] - q_plan_prev_[j]) / dt : 0.0;
      const double ddq = plan_valid_ ? (dq - rate_[j]) / dt : 0.0;
      rate_[j] = dq;
      dq_ref_[j] = dq;
      if (i == w.gait.swing) {
        tau_ff_[j] += walk_options_.inertia_feedforward * h.default_kp[j] / w2 * ddq;
        tau_ff_[j] = std::clamp(tau_ff_[j], -h.tau_max[j], h.tau_max[j]);
      }
    }
  }
  CountLandings(s, w.t);
  LogRow(w, out);
}

//---------------- landings, measured ----------------

double WalkController::FootLoad(const shm::SensorBlock& s, int foot) const noexcept {
  const double* f = s.force[force_[foot]].force;
  return std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
}

void WalkController::CountLandings(const shm::SensorBlock& s, double t) noexcept {
  double load[2];
  for (int i = 0; i < 2; ++i) load[i] = end_load_[i] = FootLoad(s, i);
  end_tilt_ = base_tilt();
  // step k landed when, within a quarter of its duration of its planned landing, its foot's
  // sensor carries a tenth of the weight; past that window it did not land. The window lasts
  // at least until the next step begins: after the last step, until the ZMP has reached the
  // middle of the final stance (the plan moves the weight onto the landed foot that slowly,
  // so it may carry less than a tenth a quarter step after landing)
  const walking::Gait& gait = gen_.gait();
  while (next_to_land_ < gait.step_count()) {
    const int k = next_to_land_;
    const double due = gait.step_land(k);
    const double tolerance = 0.25 * (due - gait.step_begin(k));
    if (t < due - tolerance) return;
    const double weight_moved = k + 1 < gait.step_count() ? gait.step_begin(k + 1) : gait.end_time();
    const int foot = gait.step(k).foot;
    if (std::isfinite(load[foot])) window_load_ = std::max(window_load_, load[foot]);
    if (load[foot] >= land_load_) {
      ++walk_stats_.steps_done;
    } else {
      if (t <= std::max(due + tolerance, weight_moved)) return;
      if (walk_stats_.steps_missed++ == 0) {
        walk_stats_.first_missed_step = k;
        walk_stats_.first_missed_foot = foot;
        walk_stats_.first_missed_due = due;
        walk_stats_.first_missed_load = window_load_;
      }
    }
    ++next_to_land_;
    window_load_ = 0;
  }
}

void WalkController::FillWalkInput(const shm::SensorBlock& s, const walking::WalkSample& w) noexcept {
  const model::Kinematics& k = *kin_est_;
  const model::BaseEstimate& e = estimator_->estimate();
  const Eigen::Matrix3d R = Rz(frame_yaw_);
  input_.c = ToPlan(e.p_WCoM);
  input_.dc = R * e.v_WCoM;
  input_.c_ref = w.com.head<2>();
  input_.dc_ref = w.dcom.head<2>();
  input_.ddc_ref = w.ddcom.head<2>();
  input_.zmp_ref_offset = w.zmp_swing;
  c_ref_ = input_.c_ref;
  input_.mass = k.mass();
  input_.heading = Wrap(frame_yaw_ + YawOf(e.quat_WB.toRotationMatrix()));
  double ground = 0;
  int n = 0;
  for (int i = 0; i < 2; ++i) {
    const shm::ForceTorque& ft = s.force[force_[i]];
    const Eigen::Matrix3d R_WS = R * k.R_WSite(sensor_site_[i]);
    FootWrench& fw = input_.feet[i];
    fw.p_WS = ToPlan(k.p_WSite(sensor_site_[i]));
    fw.f_W = R_WS * Eigen::Vector3d(ft.force[0], ft.force[1], ft.force[2]);
    fw.n_W = R_WS * Eigen::Vector3d(ft.torque[0], ft.torque[1], ft.torque[2]);
    // the sole's tilt in the plan frame
    const Eigen::Vector3d nrm = R * (k.R_WSole(sole_[i]) * Eigen::Vector3d::UnitZ());
    input_.sole_tilt[i] = Eigen::Vector2d(std::atan2(-nrm.y(), nrm.z()),
                                          std::asin(std::clamp(nrm.x(), -1.0, 1.0)));
    const model::SoleMap& sole = k.soles()[sole_[i]];
    Support& sup = input_.support;
    sup.centre[i] = w.gait.feet.p[i].head<2>();
    sup.half_size[i] = Eigen::Vector2d(sole.half_size[0], sole.half_size[1]);
    sup.yaw[i] = w.gait.feet.yaw[i];
    // a sole resting across an edge of the terrain bears only where it touches
    const walking::Footstep* on = gen_.gait().Standing(i, w.t);
    if (on && on->contact_half.x() >= 0 && w.gait.support[i]) {
      sup.centre[i] += Eigen::Rotation2Dd(on->yaw) * on->contact_centre;
      sup.half_size[i] = on->contact_half;
    }
    sup.supporting[i] = w.gait.support[i];
    if (w.gait.support[i]) {
      ground += w.gait.feet.p[i].z() + foot_dz_[i];
      ++n;
    }
  }
  input_.support.ground_z = n > 0 ? ground / n : w.gait.zmp.z();
}

void WalkController::SolveWalkJoints(const StabilizerOutput& out, const walking::WalkSample& w,
                                     double z_offset) noexcept {
  for (int j = 0; j < njoint(); ++j) q_ik_[j] = std::isfinite(q_ik_[j]) ? q_ik_[j] : ramp_target_[j];
  // while a step up found by touch has the trailing leg on the lower ground, the hip strategy's
  // torso pitch is limited (kStepUpTorsoPitch): the pelvis it moves stretched that leg straight
  const double pitch_max = rise_foot_ >= 0 ? kStepUpTorsoPitch : std::numeric_limits<double>::infinity();
  if (torso_pitch_joint_ >= 0)
    q_ik_[torso_pitch_joint_] = target_[torso_pitch_joint_] + std::clamp(out.torso_pitch, -pitch_max, pitch_max);
  if (torso_roll_joint_ >= 0) q_ik_[torso_roll_joint_] = target_[torso_roll_joint_] + out.torso_roll;
  const walking::FeetPose& f = w.gait.feet;
  Eigen::Vector3d p[2];
  Eigen::Matrix3d Rs[2];
  for (int i = 0; i < 2; ++i) {
    const double side = i == 0 ? 0.5 : -0.5;
    p[i] = f.p[i] + Eigen::Vector3d(0, 0, side * out.dz + foot_dz_[i]);
    Rs[i] = Rx(out.foot_roll[i]) * Ry(out.foot_pitch[i]) * Rz(f.yaw[i]) * R0_[i];
  }
  // the swing foot is placed against the ground, not against an upright body: the base's
  // measured tilt (roll and pitch: a stance ankle that yields) would put it lower ahead of a
  // forward lean and land it early; its target is turned back about the stance sole by that tilt
  if (w.gait.swing >= 0 && walk_options_.swing_tilt_compensation > 0) {
    const int sw = w.gait.swing, st = 1 - sw;
    // the tilt about the plan's axes (the base's orientation in the plan frame, its yaw taken
    // off on the right): the feet's offsets below are in the plan frame at any heading
    const Eigen::Matrix3d R_PB = Rz(frame_yaw_) * estimator_->estimate().quat_WB.toRotationMatrix();
    // (less the roll the legs' solution gives the base on purpose: legs without an ankle roll)
    const Eigen::Matrix3d R_tilt = R_PB * Rz(-YawOf(R_PB)) * Rx(-roll_);
    const Eigen::AngleAxisd aa(R_tilt.transpose());
    const Eigen::Matrix3d R_back(Eigen::AngleAxisd(walk_options_.swing_tilt_compensation * aa.angle(), aa.axis()));
    p[sw] = p[st] + R_back * (p[sw] - p[st]);
    Rs[sw] = R_back * Rs[sw];
  }
  const double yaw_a = f.yaw[0] - sole_yaw_B_[0], yaw_b = f.yaw[1] - sole_yaw_B_[1];
  const Eigen::Quaterniond quat(Eigen::AngleAxisd(yaw_a + 0.5 * Wrap(yaw_b - yaw_a), Eigen::Vector3d::UnitZ()));
  Eigen::Vector3d com = w.com;
  com.head<2>() += out.com_offset;
  com.z() += z_offset;
  std::array<double, shm::kMaxJoints> trial = q_ik_;
  Eigen::Vector3d p_WB = p_WB_;
  double weights[3];
  SoleWeights(w.gait, weights);
  double roll = roll_;
  const walking::WalkIkResult r = walk_ik_->Solve(com, quat, p, Rs, weights, trial.data(), &p_WB, &roll);
  CountIk(!r.ok);
  if (r.ok) {
    q_ik_ = trial;
    p_WB_ = p_WB;
    roll_ = roll;
  } else {
    if (walk_stats_.ik_failures++ == 0) {
      walk_stats_.first_ik_failure = w.t;
      walk_stats_.first_ik_failure_what =
          r.leg[0] != model::IkStatus::kConverged ? 0 : r.leg[1] != model::IkStatus::kConverged ? 1 : 2;
    }
  }
  for (int j = 0; j < njoint(); ++j) q_ref_[j] = q_ik_[j];

  // the plan alone (no stabilizer correction): the velocity references come from it
  for (int i = 0; i < 2; ++i) {
    p[i] = f.p[i] + Eigen::Vector3d(0, 0, foot_dz_[i]);
    Rs[i] = Rx(f.roll[i]) * Ry(f.pitch[i]) * Rz(f.yaw[i]) * R0_[i];
  }
  com = w.com;
  com.z() += z_offset;
  if (!plan_valid_) q_plan_ = q_ik_;
  q_plan_prev_ = q_plan_;
  trial = q_plan_;
  p_WB = p_WB_plan_;
  roll = roll_plan_;
  if (walk_ik_->Solve(com, quat, p, Rs, weights, trial.data(), &p_WB, &roll).ok) {
    q_plan_ = trial;
    p_WB_plan_ = p_WB;
    roll_plan_ = roll;
    if (!plan_valid_) q_plan_prev_ = q_plan_;  // the first solution: no rate yet
    plan_valid_ = true;
  }
}

void WalkController::SoleWeights(const walking::GaitState& g, double weights[3]) noexcept {
  // legs without an ankle roll (WalkIk::rolls_base): a supporting sole comes out flat, the
  // swinging one as the base's roll leaves it until the last fifth of its swing, where it is
  // brought flat for the landing; the CoM's sideways place as planned (the base's roll about
  // the hips standing over the flat soles moves it)
  const double land = std::clamp((g.swing_phase - 0.8) / 0.2, 0.0, 1.0);
  for (int i = 0; i < 2; ++i) weights[i] = g.support[i] ? 1.0 : land * land * (3 - 2 * land);
  weights[2] = 1.0;
}

void WalkController::LogRow(const walking::WalkSample& w, const StabilizerOutput& out) noexcept {
  if (walk_options_.log_file.empty() || log_.size() >= log_.capacity()) return;
  const walking::FeetPose& f = w.gait.feet;
  log_.push_back({w.t, w.com.x(), w.com.y(), w.com.z(), input_.c.x(), input_.c.y(), input_.c.z(),
                  w.gait.zmp.x(), w.gait.zmp.y(), out.zmp_desired.x(), out.zmp_desired.y(),
                  out.zmp_measured.x(), out.zmp_measured.y(), out.dcm.x(), out.dcm.y(),
                  f.p[0].x(), f.p[0].y(), f.p[0].z(), f.yaw[0], f.p[1].x(), f.p[1].y(), f.p[1].z(),
                  f.yaw[1], w.gait.support[0] ? 1.0 : 0.0, w.gait.support[1] ? 1.0 : 0.0,
                  frame_p_.x(), frame_p_.y(), frame_yaw_, out.foot_roll[0], out.foot_pitch[0],
                  out.foot_roll[1], out.foot_pitch[1], roll_});
}

}  // namespace ohrp::controllers
