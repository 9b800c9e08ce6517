// The walk controller's commands (the next one, the steps remapped onto the plan frame, a stop)
// and the plan frame itself (see walk.h; the cycle: walk.cc).
#include <algorithm>
#include <cmath>

#include "controllers/walk.h"
#include "walk_geometry.h"

namespace ohrp::controllers {
namespace {

constexpr double kFrameFilter = 0.1;  // [s] time constant of the plan frame's corrections

}  // namespace

using walk_geometry::Rz;
using walk_geometry::Wrap;
using walk_geometry::YawOf;

//---------------- commands ----------------

void WalkController::NextCommand(double now) noexcept {
  if (gen_.walking() || now < ready_time_) return;
  while (next_command_ < static_cast<int>(chunks_plan_.size())) {
    const WalkCommand& c = walk_options_.commands[next_command_];
    const std::vector<walking::Footstep>& steps = chunks_plan_[next_command_];
    ++next_command_;
    ++walk_stats_.commands_done;
    if (c.kind == WalkCommand::Kind::kWait) {
      ready_time_ = now + c.time;
      return;
    }
    if (steps.empty()) continue;  // e.g. a goal where the robot stands
    chunk_ = next_command_ - 1;
    chunk_first_ = gen_.Replace(steps);
    last_started_ = -2;  // remap at once
    Remap();
    return;
  }
}

void WalkController::Remap() noexcept {
  // the steps of the command under way that have not begun, moved by how far the estimate has
  // drifted from the plan since the walk started (the frame's change): they are where the
  // command put them relative to the robot's start as the robot measures it (leg odometry and
  // gyro), not only relative to where the plan thinks the feet are
  if (chunk_ < 0) return;
  const walking::Gait& gait = gen_.gait();
  // Replace keeps the steps begun at the generator's time (one period behind the sensors')
  const int k = gait.StartedBy(gen_.sample().t);
  if (k == last_started_) return;
  last_started_ = k;
  const std::vector<walking::Footstep>& original = chunks_plan_[chunk_];
  const int first = std::max(0, k + 1 - chunk_first_);  // index in the command's steps
  if (first >= static_cast<int>(original.size())) return;
  const double dyaw = Wrap(frame_yaw_ - frame0_yaw_);
  const Eigen::Matrix3d R = Rz(dyaw);
  // each moved step is kept within the step limits against the feet it steps from: the step
  // under way was moved by the frame of an earlier remap, so a frame that turned since (a stance
  // sole that twisted) can put the next step onto that sole; it is set back to the nearest place
  // the limits allow (walking::FitStep), and counted
  walking::FeetPose feet = gait.FeetAfter(std::max(k, chunk_first_ - 1));
  remap_.resize(original.size() - first);
  for (size_t n = 0; n < remap_.size(); ++n) {
    walking::Footstep s = original[first + n];
    const Eigen::Vector3d p = R * (s.p - frame0_p_) + frame_p_;
    s.p.head<2>() = p.head<2>() + recovery_shift_;
    s.yaw = Wrap(s.yaw + dyaw);
    const double yaw = s.yaw;
    const double moved = walking::FitStep(feet, &s, walk_options_.limits);
    // counted for the next step only: it is the one walked as fitted (the later ones are moved
    // again when it begins)
    if (n == 0 && (moved > 0 || s.yaw != yaw)) {
      ++walk_stats_.steps_fitted;
      walk_stats_.max_fit = std::max(walk_stats_.max_fit, moved);
      walk_stats_.max_fit_yaw = std::max(walk_stats_.max_fit_yaw, std::abs(Wrap(s.yaw - yaw)));
    }
    remap_[n] = s;
    feet = walking::After(feet, s);
  }
  gen_.Replace(remap_);
}

void WalkController::Stop() noexcept {
  // the last step that has begun lands; the other foot closes beside it; no further command
  walk_stats_.stopped = true;
  next_command_ = static_cast<int>(chunks_plan_.size());
  chunk_ = -1;
  const walking::Gait& gait = gen_.gait();
  const int k = gait.StartedBy(gen_.sample().t);
  if (k < 0 || !gen_.walking()) {
    gen_.Replace({});  // nothing begun: drop what is planned
    return;
  }
  const walking::FeetPose feet = gait.FeetAfter(k);
  const int landed = gait.step(k).foot;
  const double side = landed == walking::kLeft ? -1.0 : 1.0;  // where the other foot goes
  walking::Footstep& close = stop_steps_[0];
  close = walking::Footstep{};
  close.foot = 1 - landed;
  close.yaw = feet.yaw[landed];
  close.p = feet.p[landed] + Rz(close.yaw) * Eigen::Vector3d(0, side * walk_options_.limits.width, 0);
  gen_.Replace(stop_steps_);
}

//---------------- the plan frame ----------------

void WalkController::UpdateFrame(double dt, bool first) noexcept {
  // from each foot that supports in the plan and is in contact for the estimator
  const walking::GaitState& g = gen_.sample().gait;
  const model::BaseEstimate& e = estimator_->estimate();
  const model::Kinematics& k = *kin_est_;
  double dyaw = 0;
  int n = 0;
  double yaw_meas[2] = {0, 0};
  for (int i = 0; i < 2; ++i) {
    if (!g.support[i] || !e.contact[i]) continue;
    yaw_meas[i] = Wrap(g.feet.yaw[i] - (YawOf(k.R_WSole(sole_[i])) - sole_yaw_B_[i]));
    dyaw += yaw_meas[i];
    ++n;
  }
  if (n == 0) return;  // in the air (or a foot not yet loaded): the frame stays
  dyaw /= n;
  const Eigen::Matrix3d R = Rz(dyaw);
  Eigen::Vector3d c_est = Eigen::Vector3d::Zero(), c_plan = Eigen::Vector3d::Zero();
  for (int i = 0; i < 2; ++i) {
    if (!g.support[i] || !e.contact[i]) continue;
    c_est += k.p_WSole(sole_[i]) / n;
    c_plan += (g.feet.p[i] + Eigen::Vector3d(0, 0, foot_dz_[i])) / n;  // where it touched
  }
  // the measured frame maps c_est onto c_plan with the yaw dyaw; the filtered one moves
  // towards it about the feet (not about the world's origin, where a small yaw error would be a
  // large translation)
  const Eigen::Vector3d p = c_plan - R * c_est;
  if (first) {
    frame_yaw_ = dyaw;
    frame_p_ = p;
    return;
  }
  const double a = std::min(1.0, dt / kFrameFilter);
  const Eigen::Vector3d at_feet = ToPlan(c_est);
  walk_stats_.max_frame_drift = std::max(walk_stats_.max_frame_drift, (c_plan - at_feet).norm());
  frame_yaw_ = Wrap(frame_yaw_ + a * Wrap(dyaw - frame_yaw_));
  frame_p_ = at_feet + a * (c_plan - at_feet) - Rz(frame_yaw_) * c_est;
}

Eigen::Vector3d WalkController::ToPlan(const Eigen::Vector3d& p_est) const {
  return Rz(frame_yaw_) * p_est + frame_p_;
}

}  // namespace ohrp::controllers
