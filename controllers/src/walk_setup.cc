// The walk controller's set-up: options, the generator, the legs' IK, the commands planned into
// footsteps (see walk.h).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cli/plausible.h"
#include "controllers/pose.h"
#include "controllers/walk.h"
#include "robot_model/output_file.h"
#include "robot_model/profile.h"
#include "walking/footstep_file.h"
#include "walk_geometry.h"

namespace ohrp::controllers {
namespace {

ConfigStatus CheckWalkOptions(const WalkOptions& o) {
  auto bad = [](const std::string& what) { return ConfigStatus::Fail(ConfigError::kOption, what); };
  if (const std::string e = walking::CheckGaitOptions(o.gait); !e.empty()) return bad(e);
  if (!(std::isfinite(o.com_lower) && o.com_lower >= 0 && o.com_lower <= 0.2))
    return bad("com_lower must be in [0, 0.2] m (got " + std::to_string(o.com_lower) + ")");
  if (!(std::isfinite(o.lower_time) && o.lower_time >= 0.1 && o.lower_time <= 10))
    return bad("lower_time must be in [0.1, 10] s");
  if (!(std::isfinite(o.preview.preview_time) && o.preview.preview_time >= 0.5 &&
        o.preview.preview_time <= 5))
    return bad("preview_time must be in [0.5, 5] s (Kajita 2003: about 1.6 s)");
  if (!(std::isfinite(o.swing_tilt_compensation) && o.swing_tilt_compensation >= 0 &&
        o.swing_tilt_compensation <= 1))
    return bad("swing_tilt_compensation must be in [0, 1]");
  if (!(std::isfinite(o.inertia_feedforward) && o.inertia_feedforward >= 0 &&
        o.inertia_feedforward <= 2))
    return bad("inertia_feedforward must be in [0, 2]");
  if (!(std::isfinite(o.swing_zmp) && o.swing_zmp >= 0 && o.swing_zmp <= 1))
    return bad("swing_zmp must be in [0, 1]");
  if (!(std::isfinite(o.step_search) && o.step_search >= 0 && o.step_search <= 0.2))
    return bad("step_search must be in [0, 0.2] m");
  if (!(std::isfinite(o.log_seconds) && o.log_seconds > 0 && o.log_seconds <= 36000))
    return bad("--log-seconds must be in (0, 36000] s");
  return ConfigStatus::Ok();
}

}  // namespace

using walk_geometry::YawOf;

std::unique_ptr<WalkController> WalkController::Create(const WalkOptions& options,
                                                       ConfigStatus* status) {
  WalkOptions o = options;
  // the robot profile's walking parameters, then the parameter file's; what the command line
  // set (the keys already given) stays
  const std::vector<std::string> command_line = o.given;
  if (model::IsProfilePath(o.balance.model)) {
    *status = LoadProfileWalkParams(o.balance.model, &o, command_line);
    if (!status->ok()) return nullptr;
  }
  if (!o.params_file.empty()) {
    *status = LoadWalkParams(o.params_file, &o, command_line);
    if (!status->ok()) return nullptr;
  }
  *status = CheckWalkOptions(o);
  if (!status->ok()) return nullptr;
  BalanceOptions filled;
  Pose pose;
  std::unique_ptr<model::Kinematics> kin_est, kin_ik;
  o.balance.one_leg.sides.clear();  // walking, not standing on one leg
  o.balance.centre_com = true;
  *status = LoadParts(o.balance, "walk", &filled, &pose, &kin_est, &kin_ik);
  if (!status->ok()) return nullptr;
  std::unique_ptr<WalkController> walk(
      new WalkController(o, filled, std::move(pose), std::move(kin_est), std::move(kin_ik)));
  // the commands planned on the model now, before anything attaches: a footstep file or an
  // option that does not fit the robot is refused here
  *status = walk->Preflight();
  if (!status->ok()) return nullptr;
  return walk;
}

WalkController::WalkController(const WalkOptions& options, const BalanceOptions& filled, Pose pose,
                               std::unique_ptr<model::Kinematics> kin_est,
                               std::unique_ptr<model::Kinematics> kin_ik)
    : BalanceController(filled, std::move(pose), std::move(kin_est), std::move(kin_ik)),
      walk_options_(options) {
  walk_options_.balance = filled;
}

ConfigStatus WalkController::on_configure(const shm::SegmentHeader& header) {
  if (ConfigStatus s = BalanceController::on_configure(header); !s.ok()) return s;
  std::string error;
  walk_ik_ = walking::WalkIk::Create(kin_ik_.get(), &error);
  if (!walk_ik_) return ConfigStatus::Fail(ConfigError::kMismatch, error);
  if (ConfigStatus s = FitStance(target_.data()); !s.ok()) return s;
  // the generator at the control period and the walking CoM height
  walking::PreviewOptions po = walk_options_.preview;
  po.dt = header.control_period;
  po.zc = zc_;
  if (!gen_.Configure(walk_options_.gait, po, &error))
    return ConfigStatus::Fail(ConfigError::kOption, error);
  if (ConfigStatus s = LoadTerrain(); !s.ok()) return s;
  if (ConfigStatus s = PlanCommands(); !s.ok()) return s;
  land_load_ = 0.1 * kin_est_->mass() * 9.81;
  touch_load_ = 0.5 * land_load_;
  // what the cycle needs, allocated now
  int total = 0;
  for (const auto& c : chunks_) total += static_cast<int>(c.size());
  walk_stats_.steps_planned = total;
  gen_.Reserve(total + 8);
  chunks_plan_ = chunks_;
  stop_steps_.assign(1, walking::Footstep{});
  size_t longest = 0;
  for (const auto& c : chunks_) longest = std::max(longest, c.size());
  remap_.reserve(longest);
  if (ConfigStatus s = OpenChannel(); !s.ok()) return s;
  if (!walk_options_.log_file.empty())
    log_.reserve(static_cast<size_t>(walk_options_.log_seconds / header.control_period) + 1);
  return ConfigStatus::Ok();
}

ConfigStatus WalkController::Preflight() {
  // the stance pose on the model's joints (the producer's robot is checked against this model
  // at configure: the same joints, in the same order)
  std::vector<std::string> names;
  for (const model::JointMap& j : kin_ik_->robot().joints) names.push_back(j.name);
  std::vector<double> q;
  if (ConfigStatus s = ResolvePose(pose_, names, &q); !s.ok()) return s;
  q.resize(shm::kMaxJoints, 0.0);
  if (ConfigStatus s = FitStance(q.data()); !s.ok()) return s;
  if (ConfigStatus s = LoadTerrain(); !s.ok()) return s;
  std::string error;  // the log is written at the end: a path it cannot be written to is refused now
  if (!walk_options_.log_file.empty() &&
      !model::PrepareOutputFile(walk_options_.log_file, "# walk: the run is under way\n", &error))
    return ConfigStatus::Fail(ConfigError::kFile, "--log: " + error);
  return PlanCommands();
}

ConfigStatus WalkController::LoadTerrain() {
  if (walk_options_.terrain.empty() || terrain_) return ConfigStatus::Ok();
  std::string error;
  terrain_ = walking::TerrainMap::Load(walk_options_.terrain, walk_options_.keyframe, &error);
  if (!terrain_) return ConfigStatus::Fail(ConfigError::kFile, "--terrain: " + error);
  return ConfigStatus::Ok();
}

double WalkController::LegLength(Eigen::Vector3d* hip) const {
  // hip joint to sole along the left leg's joints: the distances between successive joint
  // anchors (each on its joint's axis, so the same in every posture) and on to the sole's centre
  const model::Kinematics& k = *kin_ik_;
  const mjModel* m = k.m();
  const model::SoleMap& sole = k.soles()[k.left_sole()];
  double length = 0;
  bool first = true;
  Eigen::Vector3d last = Eigen::Vector3d::Zero();
  for (int j : k.Chain(k.robot().base_body, sole.body_id)) {
    const int jid = k.robot().joints[j].joint_id;
    const int body = m->jnt_bodyid[jid];
    const Eigen::Vector3d anchor =
        k.p_WBody(body) + k.R_WBody(body) * Eigen::Vector3d(m->jnt_pos[3 * jid],
                                                            m->jnt_pos[3 * jid + 1],
                                                            m->jnt_pos[3 * jid + 2]);
    if (!first) length += (anchor - last).norm();
    if (first && hip) *hip = anchor;
    first = false;
    last = anchor;
  }
  return first ? 0.0 : length + (k.p_WSole(k.left_sole()) - last).norm();
}

void WalkController::SetSwingZmp(double hip_stance, double sole_z) {
  // the left leg's bodies (hip joint to sole) at their stance heights scaled to the walking hip
  // height (the CoM lowered by bending the legs); the preview plans against their ZMP share
  const model::Kinematics& k = *kin_ik_;
  const mjModel* m = k.m();
  const int sole_body = k.soles()[k.left_sole()].body_id;
  const double hip = walk_options_.gait.hip_height;
  std::vector<walking::LegBody> leg;
  std::vector<int> bodies;
  for (int j : k.Chain(k.robot().base_body, sole_body)) bodies.push_back(m->jnt_bodyid[k.robot().joints[j].joint_id]);
  bodies.push_back(sole_body);
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  for (int b : bodies) {
    const Eigen::Vector3d c = k.p_WBody(b) + k.R_WBody(b) * Eigen::Vector3d(m->body_ipos[3 * b],
                                                                           m->body_ipos[3 * b + 1],
                                                                           m->body_ipos[3 * b + 2]);
    leg.push_back({m->body_mass[b], (c.z() - sole_z) * hip / std::max(hip_stance, 1e-6)});
  }
  swing_zmp_gain_ = walking::SwingZmpGain(leg, hip, zc_, k.mass());
  leg_mass_ = leg_depth_ = 0;
  for (const walking::LegBody& b : leg) {
    leg_mass_ += b.mass;
    leg_depth_ += b.mass * (hip - b.height);
  }
  leg_depth_ /= std::max(leg_mass_, 1e-9);
  gen_.SetSwingZmpGain(walk_options_.swing_zmp * swing_zmp_gain_);
}

ConfigStatus WalkController::FitStance(const double* q) {
  // the stance (base upright at the origin): the soles' nominal poses, the CoM height
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(q);
  kin_ik_->Update();
  const int soles[2] = {kin_ik_->left_sole(), kin_ik_->right_sole()};
  Eigen::Vector3d p[2];
  Eigen::Matrix3d R[2];
  for (int i = 0; i < 2; ++i) {
    p[i] = kin_ik_->p_WSole(soles[i]);
    R[i] = kin_ik_->R_WSole(soles[i]);
  }
  const Eigen::Vector3d mid = 0.5 * (p[0] + p[1]);
  for (int i = 0; i < 2; ++i) {
    sole_yaw_B_[i] = YawOf(R[i]);
    R0_[i] = Eigen::AngleAxisd(-sole_yaw_B_[i], Eigen::Vector3d::UnitZ()) * R[i];
    nominal_.p[i] = p[i] - mid;
    nominal_.p[i].z() = 0;
    nominal_.yaw[i] = sole_yaw_B_[i];
  }
  zc_ = kin_ik_->p_WCoM().z() - mid.z() - walk_options_.com_lower;
  Eigen::Vector3d hip = mid;
  walking::StepLimits& lim = walk_options_.limits;
  lim.width = (p[0] - p[1]).head<2>().norm();
  const model::SoleMap& sole = kin_ik_->soles()[soles[0]];
  lim.sole_half_size = Eigen::Vector2d(sole.half_size[0], sole.half_size[1]);
  walk_options_.gait.sole_half_length = sole.half_size[0];
  walk_options_.gait.sole_half_width = sole.half_size[1];
  walk_options_.gait.swing_clearance = lim.clearance;
  lim.min_width = std::min(lim.min_width, lim.width);
  if (const std::string e = walking::CheckLimits(lim); !e.empty())
    return ConfigStatus::Fail(ConfigError::kOption, "step limits: " + e);
  const double leg = LegLength(&hip);
  DeriveGait(leg);
  // the legs' reach for steps down (walking::StepDownDrop): a leg stretched to kLegReach of its
  // length (the knee still bent, away from its singularity), the hip joint at the walking height
  constexpr double kLegReach = 0.95;
  walk_options_.gait.leg_reach = kLegReach * leg;
  walk_options_.gait.hip_height = hip.z() - mid.z() - walk_options_.com_lower;
  SetSwingZmp(hip.z() - mid.z(), mid.z());
  // a recovery step (the stepping strategy) may go as far as that leg reaches from the hip at
  // the walking height, beyond the planner's limits: r = sqrt(reach^2 - hip height^2) ahead,
  // behind, or beside the hip (half the width beside the stance sole)
  const double r2 = std::pow(walk_options_.gait.leg_reach, 2) - std::pow(walk_options_.gait.hip_height, 2);
  recovery_limits_ = lim;
  if (r2 > 0) {
    const double r = walk_options_.stepping_reach * std::sqrt(r2);
    recovery_limits_.max_forward = std::max(lim.max_forward, r);
    recovery_limits_.max_backward = std::max(lim.max_backward, r);
    recovery_limits_.max_side = std::max(lim.max_side, r - 0.5 * lim.width);
  }
  return FitPhysics(leg);
}

ConfigStatus WalkController::FitPhysics(double leg) {
  // from the robot (docs/footsteps.md): no step longer than a leg, no rise or swing apex above
  // a third of it, no step faster than the walking pendulum's time constant sqrt(zc / g)
  char basis[200];
  const double tau = std::sqrt(std::max(zc_, 1e-3) / 9.81);
  std::snprintf(basis, sizeof basis,
                "from the model: leg length %.3f m, walking CoM height %.3f m, pendulum time "
                "%.2f s",
                leg, zc_, tau);
  walking::StepLimits& lim = walk_options_.limits;
  lim.physics_basis = basis;
  if (!(leg > 0)) return ConfigStatus::Ok();  // no leg chain found: the table's ranges hold
  lim.max_rise = leg / 3;
  lim.max_apex = leg / 3;
  const cli::PlausibleRange* step_time = cli::FindPlausible("step_time");
  lim.min_duration = std::max(step_time->lo, tau);
  lim.max_duration = step_time->hi;
  auto beyond = [&](const char* what, double v, double hi) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "%s = %g m is beyond this robot's range [0, %.3f] m (%s)",
                  what, v, hi, basis);
    return ConfigStatus::Fail(ConfigError::kOption, buf);
  };
  if (lim.max_forward > leg) return beyond("--max-stride (max_forward)", lim.max_forward, leg);
  if (lim.max_backward > leg) return beyond("max_backward", lim.max_backward, leg);
  if (lim.width + lim.max_side > leg) return beyond("width + max_side", lim.width + lim.max_side, leg);
  const walking::GaitOptions& g = walk_options_.gait;
  if (g.step_height > lim.max_apex) return beyond("--step-height", g.step_height, lim.max_apex);
  if (g.step_time < lim.min_duration || g.step_time > lim.max_duration) {
    char buf[400];
    std::snprintf(buf, sizeof buf, "--step-time = %g s is outside this robot's range [%.3f, %g] s (%s)",
                  g.step_time, lim.min_duration, lim.max_duration, basis);
    return ConfigStatus::Fail(ConfigError::kOption, buf);
  }
  // within the leg's reach: then what its joints can swing
  return FitSwing();
}

ConfigStatus WalkController::FitSwing() {
  // the longest forward step's swing (from max_forward behind to max_forward ahead) against what
  // the left hip pitch joint (the first joint of the leg turning about the base's y axis) can
  // accelerate: its torque limit less the leg's gravity load where the swing's acceleration
  // peaks, over its inertia in the stance (the mass matrix's diagonal: the leg's and the
  // rotor's), at the foot hip_height below it
  model::Kinematics& k = *kin_ik_;
  const mjModel* m = k.m();
  const int sole_body = k.soles()[k.left_sole()].body_id;
  int hip_pitch = -1;
  for (int j : k.Chain(k.robot().base_body, sole_body)) {
    const int jid = k.robot().joints[j].joint_id;
    const Eigen::Vector3d axis = k.R_WBody(m->jnt_bodyid[jid]) *
                                 Eigen::Vector3d(m->jnt_axis[3 * jid], m->jnt_axis[3 * jid + 1], m->jnt_axis[3 * jid + 2]);
    if (std::abs(axis.y()) > 0.9) {
      hip_pitch = j;
      break;
    }
  }
  const walking::GaitOptions& g = walk_options_.gait;
  const double tau_max = hip_pitch >= 0 ? k.robot().joints[hip_pitch].tau_max : 0;
  if (hip_pitch < 0 || !(tau_max > 0) || tau_max >= model::kNoLimit || !(g.hip_height > 0))
    return ConfigStatus::Ok();
  Eigen::MatrixXd M(k.nv(), k.nv());
  k.MassMatrix(M);
  const int col = k.base_columns() + hip_pitch;
  const double stride = walk_options_.limits.max_forward;
  // at the peak (the minimum-jerk profile's s = 1/2 - sqrt(3)/6) the foot has travelled f(s) of
  // its 2 strides: it is (1 - 2 f(s)) = 0.866 of a stride behind the hip (over the stance sole)
  double f, df, ddf;
  walking::MinJerk(0.5 - std::sqrt(3.0) / 6, &f, &df, &ddf);
  const double behind = (1 - 2 * f) * stride;
  const double tau_g = leg_mass_ * 9.81 * leg_depth_ * std::sin(std::atan2(behind, g.hip_height));
  const double limit = walking::SwingAccelerationLimit(tau_max, tau_g, M(col, col), g.hip_height);
  swing_accel_limit_ = limit;
  const double need = walking::SwingPeakAcceleration(g, 2 * stride);
  if (need <= limit) return ConfigStatus::Ok();
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "max_forward %.3f m at %.3f s steps (double support %.2f, vertical share %.2f) "
                "swings the foot at up to %.1f m/s^2; the legs reach %.1f m/s^2 (%s: %.0f N m "
                "less %.0f N m of gravity, over %.1f kg m^2, the foot %.3f m below): a shorter "
                "max_forward, longer steps or a smaller double support or vertical share",
                stride, g.step_time, g.double_support_ratio, g.vertical_fraction, need, limit,
                k.robot().joints[hip_pitch].name.c_str(), tau_max, tau_g, M(col, col),
                g.hip_height);
  return ConfigStatus::Fail(ConfigError::kOption, buf);
}

ConfigStatus WalkController::PlanCommands() {
  chunks_.clear();
  notes_.clear();
  walking::FeetPose feet = nominal_;
  const walking::StepLimits& lim = walk_options_.limits;
  for (const WalkCommand& c : walk_options_.commands) {
    std::vector<walking::Footstep> steps;
    std::string error, note;
    if (terrain_ && c.kind == WalkCommand::Kind::kGoal) {
      // a goal across the terrain: one level (stair) at a time (walking/terrain.h)
      if (!terrain_->PlanGoalAcross(feet, c.x, c.y, c.yaw, lim, walk_options_.step_search, &steps,
                                    &error, &note))
        return ConfigStatus::Fail(ConfigError::kOption, "\"" + c.text + "\" on --terrain " +
                                                            walk_options_.terrain + ": " + error);
      if (!note.empty()) notes_.push_back("\"" + c.text + "\": " + note);
    } else {
      if (!PlanWalkCommand(c, feet, lim, walk_options_.gait.step_time, &steps, &note, &error))
        return ConfigStatus::Fail(ConfigError::kOption, error);
      if (!note.empty()) notes_.push_back("\"" + c.text + "\": " + note);
      if (terrain_ && !terrain_->PlaceSteps(&steps, feet, lim, walk_options_.step_search, &error))
        return ConfigStatus::Fail(ConfigError::kOption, "\"" + c.text + "\" on --terrain " +
                                                            walk_options_.terrain + ": " + error);
    }
    // the steps moved off edges must still keep the limits
    if (const std::string e = walking::CheckSteps(feet, steps, lim); terrain_ && !e.empty())
      return ConfigStatus::Fail(ConfigError::kOption, "\"" + c.text + "\" on --terrain " +
                                                          walk_options_.terrain +
                                                          ": a step moved off an edge breaks a "
                                                          "limit: " + e);
    for (const walking::Footstep& s : steps) feet = walking::After(feet, s);
    chunks_.push_back(std::move(steps));
  }
  return ConfigStatus::Ok();
}

}  // namespace ohrp::controllers
