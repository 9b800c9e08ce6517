// The balance controller's set-up: options, the robot's requirements, the model check, the
// torso joints, the soles' nominal poses and the stance plan (see balance.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "controllers/balance.h"
#include "controllers/derived_gait.h"
#include "controllers/hip_strategy.h"
#include "controllers/posture.h"
#include "cli/data_dir.h"
#include "robot_model/model.h"
#include "robot_model/model_hash.h"
#include "robot_model/profile.h"

namespace ohrp::controllers {
namespace {

// torso joints: on the path from the base to the IMU, turning about the base's y (pitch) or x
// (roll) in the reference configuration
constexpr double kAxisAlignment = 0.95;  // |cos| between the joint axis and the base axis [-]

// Everything balance needs of the robot and the stance pose that `k` and `pose` lack, each with
// what would satisfy it (empty: nothing missing). The soles' sensors and leg chains are checked
// only when the soles are there; the F/T requirement is listed either way.
std::vector<std::string> MissingRequirements(const model::Kinematics& k, const Pose& pose) {
  std::vector<std::string> missing;
  if (!k.floating()) missing.push_back("a floating base: a free joint on the robot's root body");
  const bool soles = k.left_sole() >= 0 && k.right_sole() >= 0;
  if (!soles) {
    std::string found;
    for (const model::SoleMap& s : k.soles()) found += (found.empty() ? "" : ", ") + s.name;
    missing.push_back("two soles: a box geom whose name ends in _SOLE under each foot, its bottom "
                      "face the sole rectangle (the support polygon and the soft contact); found " +
                      std::to_string(k.soles().size()) + (found.empty() ? "" : " (" + found + ")"));
    missing.push_back("a force/torque sensor in each foot: a <force> and a <torque> sensor on one "
                      "site of the foot's body or between the ankle and the sole");
  } else {
    for (int side : {k.left_sole(), k.right_sole()}) {
      const model::SoleMap& s = k.soles()[side];
      if (s.force_sensor < 0)
        missing.push_back("a force/torque sensor above sole " + s.name + ": a <force> and a "
                          "<torque> sensor on one site of its body or of a body between it and "
                          "the base");
      if (k.floating()) {
        try {
          model::LimbIk::ForSole(k, k.robot().base_body, side);
        } catch (const std::exception& e) {
          missing.push_back("a leg from the base to sole " + s.name + " (" + e.what() + ")");
        }
      }
    }
  }
  if (k.robot().imus.empty())
    missing.push_back("an IMU: a <gyro> and an <accelerometer> sensor on one site (on the base or "
                      "the torso)");
  std::vector<std::string> names;
  for (const model::JointMap& j : k.robot().joints) names.push_back(j.name);
  std::vector<double> q;
  if (ConfigStatus s = ResolvePose(pose, names, &q); !s.ok())
    missing.push_back("a stance pose for this robot's joints (--keyframe NAME of the model, or "
                      "--pose FILE; the default is HRP-1S's): " + s.message);
  return missing;
}

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

// torso joint j as the hip strategy sees it, at kin's current (stance) configuration
TorsoAxis MeasureTorsoAxis(model::Kinematics& kin, const Eigen::MatrixXd& M, int j, double q0) {
  const mjModel* m = kin.m();
  const model::JointMap& jm = kin.robot().joints[j];
  const int jid = jm.joint_id;
  const int top = m->jnt_bodyid[jid];
  TorsoAxis a;
  const int col = kin.base_columns() + j;
  a.inertia = std::max(M(col, col) - m->dof_armature[jm.dof_adr], 1e-3);
  const Eigen::Vector3d anchor =
      kin.p_WBody(top) + kin.R_WBody(top) * Eigen::Vector3d(m->jnt_pos[3 * jid],
                                                            m->jnt_pos[3 * jid + 1],
                                                            m->jnt_pos[3 * jid + 2]);
  for (int b = top; b < m->nbody; ++b) {  // the subtree: bodies whose ancestors include `top`
    int p = b;
    while (p > top) p = m->body_parentid[p];
    if (p != top) continue;
    const Eigen::Vector3d c = kin.p_WBody(b) + kin.R_WBody(b) * Eigen::Vector3d(m->body_ipos[3 * b],
                                                                              m->body_ipos[3 * b + 1],
                                                                              m->body_ipos[3 * b + 2]);
    a.moment += m->body_mass[b] * (c.z() - anchor.z());
  }
  a.moment = std::max(a.moment, 0.0);
  const double lo = jm.q_min, hi = jm.q_max;
  a.travel = std::max(std::min(hi - q0, q0 - lo), 0.0);
  a.tau_max = jm.tau_max;
  return a;
}


// The stance leg's sag under the whole weight (o->stance_sag), and the load feed-forward when
// neither the command line nor the profile chose it: on when that sag exceeds kSagLimit
// (derived_gait.h); said on stderr with its figures. `k` is set to the stance pose (base
// upright at the origin).
ConfigStatus DeriveLoadFeedforward(model::Kinematics& k, const Pose& pose, BalanceOptions* o) {
  std::vector<std::string> names;
  for (const model::JointMap& j : k.robot().joints) names.push_back(j.name);
  std::vector<double> q;
  if (ConfigStatus s = ResolvePose(pose, names, &q); !s.ok()) return s;
  q.resize(std::max<size_t>(q.size(), names.size()), 0.0);
  k.SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  k.SetJointPositions(q.data());
  k.Update();
  const int n = static_cast<int>(names.size());
  std::vector<double> tau(n, 0.0), tau_max(n), kp(n);
  const double scale = o->servo_frequency > 0 ? o->servo_frequency / 6.0 : 1.0;
  for (int j = 0; j < n; ++j) {
    tau_max[j] = k.robot().joints[j].tau_max;
    kp[j] = k.robot().joints[j].default_kp * scale * scale;
  }
  const int sole[2] = {k.left_sole(), k.right_sole()};
  LoadFeedforward ff(k, sole);
  const double share[2] = {1, 0};  // the whole weight on the left sole, the CoM between the feet
  ff.Compute(k, share, tau_max.data(), tau.data());
  const std::vector<int> leg = k.Chain(k.robot().base_body, k.soles()[sole[0]].body_id);
  const SagEstimate s = LargestSag(leg.data(), static_cast<int>(leg.size()), tau.data(), kp.data());
  o->stance_sag = s.sag;
  if (o->load_feedforward >= 0) return ConfigStatus::Ok();  // chosen: the sag only measured
  o->load_feedforward = s.sag > kSagLimit ? 1 : 0;
  if (s.joint < 0) {
    std::fprintf(stderr, "%s: load feed-forward off (derived: no leg joint with a stiffness)\n",
                 o->program.c_str());
  } else {
    std::fprintf(stderr,
                 "%s: load feed-forward %s (derived: the stance leg carrying the whole weight "
                 "sags up to %.4f rad at %s, %.1f N m over kp %.0f N m/rad, %s the %.3f rad "
                 "limit; --load-feedforward / --no-load-feedforward or the profile's "
                 "servo.load_feedforward choose otherwise)\n",
                 o->program.c_str(), o->load_feedforward ? "on" : "off", s.sag,
                 k.robot().joints[s.joint].name.c_str(), std::abs(s.tau), s.kp,
                 o->load_feedforward ? "beyond" : "within", kSagLimit);
  }
  return ConfigStatus::Ok();
}
}  // namespace

void BalanceController::DeriveHipStrategy(StabilizerGains* g) {
  // the torso's pitch and roll joints at the stance (kin_ik_ holds it); one axis without a
  // joint takes the other's (its offset is not applied anyway)
  const model::Kinematics& k = *kin_est_;
  Eigen::MatrixXd M(kin_ik_->nv(), kin_ik_->nv());
  kin_ik_->MassMatrix(M);
  const int joint[2] = {torso_pitch_joint_, torso_roll_joint_};
  const double sole_half[2] = {k.soles()[sole_[0]].half_size[0], k.soles()[sole_[0]].half_size[1]};
  const double inertia =
      MeasureTorsoAxis(*kin_ik_, M, joint[0] >= 0 ? joint[0] : joint[1], 0).inertia;
  for (int a = 0; a < 2; ++a) {
    const int j = joint[a] >= 0 ? joint[a] : joint[1 - a];
    const TorsoAxis axis = MeasureTorsoAxis(*kin_ik_, M, j, target_[j]);
    const HipAxisLimits lim = DeriveHipAxis(axis, k.mass(), sole_half[a]);
    // the inertia: the pitch joint's on both axes (as before). Each axis' own (HRP-1S's roll
    // 4.96 against its pitch 4.19 kg m^2) made walk_fast6 tilt 5.9 deg (its limit 5; 4.6 so)
    g->torso_inertia[a] = inertia;
    g->torso_share[a] = lim.gain;
    g->torso_limit[a] = lim.max_angle;
    std::fprintf(stderr, "%s: hip strategy %s (%s): I %.3f kg m^2 (used %.3f), m_u h_u %.3f kg m, travel %.3f rad, "
                 "tau_max %.1f N m, sole half %.3f m -> gain %.3f, clamp %.3f rad\n",
                 options_.program.c_str(), a == 0 ? "pitch" : "roll",
                 k.robot().joints[j].name.c_str(), axis.inertia, inertia,
                 axis.moment, axis.travel, axis.tau_max, sole_half[a], lim.gain, lim.max_angle);
  }
}

std::string DefaultModelFile() { return cli::DataPath("mjcf/hrp1s/hrp1s.xml"); }

//---------------- set-up ----------------

ConfigStatus BalanceController::LoadParts(const BalanceOptions& options, const char* program,
                                          BalanceOptions* filled, Pose* pose,
                                          std::unique_ptr<model::Kinematics>* kin_est,
                                          std::unique_ptr<model::Kinematics>* kin_ik) {
  if (ConfigStatus s = CheckOptions(options); !s.ok()) return s;
  BalanceOptions& o = *filled;
  o = options;
  o.program = program;
  if (o.model.empty()) o.model = DefaultModelFile();
  if (o.pose_file.empty()) o.pose_file = DefaultPoseFile();
  if (o.keyframe.empty()) {
    if (ConfigStatus s = LoadPoseFile(o.pose_file, pose); !s.ok()) return s;
  }
  std::string error;
  // a robot profile's servo: the defaults of --servo-hz and --load-feedforward
  if (model::IsProfilePath(o.model)) {
    model::RobotProfile profile;
    if (!model::ReadProfile(o.model, &profile, &error))
      return ConfigStatus::Fail(ConfigError::kFile, "--model: " + error);
    if (o.servo_frequency == 0) o.servo_frequency = profile.servo_frequency;
    if (o.load_feedforward < 0 && profile.load_feedforward_given)
      o.load_feedforward = profile.load_feedforward ? 1 : 0;
  }
  *kin_est = model::Kinematics::Load(o.model, &error);
  *kin_ik = *kin_est ? model::Kinematics::Load(o.model, &error) : nullptr;
  if (!*kin_est || !*kin_ik) return ConfigStatus::Fail(ConfigError::kFile, "--model: " + error);
  if (!o.keyframe.empty()) {
    // the stance pose from the model's own keyframe (its hinge and slide joints by name)
    std::vector<std::pair<std::string, double>> joints;
    if (!model::KeyframeJointPositions((*kin_est)->m(), o.keyframe, &joints, &error))
      return ConfigStatus::Fail(ConfigError::kOption,
                                "--keyframe " + o.keyframe + ": " + o.model + ": " + error);
    *pose = FromKeyframe(o.model + " keyframe '" + o.keyframe + "'", joints);
  }
  // what balance needs of the robot: every missing requirement at once
  const model::Kinematics& k = **kin_est;
  const std::vector<std::string> missing = MissingRequirements(k, *pose);
  if (!missing.empty()) {
    std::string message = "cannot run on the robot of " + o.model + ": " +
                          std::to_string(missing.size()) + " requirement" +
                          (missing.size() > 1 ? "s" : "") + " missing (all listed):";
    for (const std::string& m : missing) message += "\n  - " + m;
    return ConfigStatus::Fail(ConfigError::kMismatch, message);
  }
  // the stance leg's sag (walk's derived stride) and, when not chosen, the feed-forward
  if (ConfigStatus s = DeriveLoadFeedforward(**kin_ik, *pose, &o); !s.ok()) return s;
  // the support margin against this robot's soles: the desired ZMP kept that far inside a sole
  // must leave some of it (less than its smallest half size)
  double half = INFINITY;
  for (int side : {k.left_sole(), k.right_sole()})
    half = std::min({half, k.soles()[side].half_size[0], k.soles()[side].half_size[1]});
  if (!(o.gains.support_margin < half)) {
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "--support-margin = %g m is outside this robot's range [0, %.3f) m (the "
                  "desired ZMP kept that far inside the soles of %s, whose smallest half size "
                  "is %.3f m, would leave no support)",
                  o.gains.support_margin, half, o.model.c_str(), half);
    return ConfigStatus::Fail(ConfigError::kOption, buf);
  }
  return ConfigStatus::Ok();
}

std::unique_ptr<BalanceController> BalanceController::Create(const BalanceOptions& options,
                                                             ConfigStatus* status) {
  BalanceOptions o;
  Pose pose;
  std::unique_ptr<model::Kinematics> kin_est, kin_ik;
  *status = LoadParts(options, "balance", &o, &pose, &kin_est, &kin_ik);
  if (!status->ok()) return nullptr;
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
    if (options_.load_feedforward > 0)
      load_ff_ = std::make_unique<LoadFeedforward>(k, sole_);
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
    DeriveHipStrategy(&g);
  }
  DeriveAnkleDamping(&g);
  // nominal soles in the base frame at the stance pose
  for (int i = 0; i < 2; ++i) {
    p_BS_nominal_[i] = kin_ik_->p_WSole(sole_[i]);
    R_BS_nominal_[i] = kin_ik_->R_WSole(sole_[i]);
  }
  // what the fall watch derives its limits from
  com_height_ = kin_ik_->p_WCoM().z() - 0.5 * (p_BS_nominal_[0].z() + p_BS_nominal_[1].z());
  sole_reach_ = k.soles()[sole_[0]].half_size[0];
  // the stance plan: centred, then on each sole asked for
  StanceShift centre, side[2];
  if (options_.centre_com &&
      !SolveShiftOver(0.5 * (p_BS_nominal_[0] + p_BS_nominal_[1]).head<2>(), &centre)) {
    // only balance has --no-centre-com; walk always starts centred
    const std::string remedy = options_.program == "balance"
                                   ? "use --no-centre-com, or a stance pose (--pose) from which "
                                     "they can"
                                   : options_.program + " starts with the CoM centred: give a "
                                     "stance pose (--pose) from which they can";
    return ConfigStatus::Fail(ConfigError::kLimits,
                              "the legs cannot move the CoM over the middle of the soles from "
                              "this stance pose (" + remedy + ")");
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

}  // namespace ohrp::controllers
