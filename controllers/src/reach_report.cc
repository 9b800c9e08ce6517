// reach's report after the run: the plan(s), the measured clearance and the final error, per
// goal with a goals file (controllers/reach.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "controllers/reach.h"
#include "controllers/reach_live.h"

namespace ohrp::controllers {
namespace {

std::string Fmt(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char text[256];
  std::snprintf(text, sizeof text, format, a, b, c, d);
  return text;
}

}  // namespace

double ReachController::HandError(const HandGoal& hand) const {
  // the base frame: the base at the origin, upright (as the goal was given)
  const int site = kin_ik_->SiteId(hand.site);
  kin_ik_->SetBasePose(Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
  kin_ik_->SetJointPositions(final_q_.data());
  kin_ik_->UpdatePositions();
  const mjModel* m = kin_ik_->m();
  // the hand: a site, else a body's frame (reach_goal.cc)
  const int body = site >= 0 ? m->site_bodyid[site] : mj_name2id(m, mjOBJ_BODY, hand.site.c_str());
  const Eigen::Vector3d p_TipT = site >= 0 ? Eigen::Vector3d(m->site_pos[3 * site], m->site_pos[3 * site + 1],
                                                             m->site_pos[3 * site + 2])
                                           : Eigen::Vector3d::Zero();
  const Eigen::Vector3d p = kin_ik_->p_WBody(body) + kin_ik_->R_WBody(body) * p_TipT;
  return (p - hand.p_B).norm();
}

const planning::Verdict& ReachController::MeasuredClearance() const {
  if (!clearance_done_) {
    clearance_done_ = true;
    clearance_ = planning::Verdict();
    clearance_.distance = INFINITY;
    clearance_.valid = true;
    const size_t nq = request_.size();
    for (size_t r = 0; r < log_rows_; ++r) {
      const planning::Verdict v =
          check_->Evaluate(std::span<const double>(log_.data() + r * nq, nq));
      if (v.distance < clearance_.distance) clearance_ = v;
    }
  }
  return clearance_;
}

ReachController::Clearances ReachController::ClearanceOfRows(size_t begin, size_t end) const {
  Clearances c;
  c.self.distance = c.scene.distance = INFINITY;
  const size_t nq = request_.size();
  planning::Verdict self, scene;
  for (size_t r = begin; r < end && r < log_rows_; ++r) {
    check_->EvaluateByKind(std::span<const double>(log_.data() + r * nq, nq), &self, &scene);
    if (self.distance < c.self.distance) c.self = self;
    if (scene.distance < c.scene.distance) c.scene = scene;
  }
  return c;
}

std::string ReachController::Describe(const Clearances& c) const {
  auto one = [&](const planning::Verdict& v) {
    if (v.a.empty()) return Fmt("above %.1f mm", 1e3 * v.distance);
    return Fmt("%.1f mm", 1e3 * v.distance) + " (" + v.a + " / " + v.b + ")";
  };
  std::string text = "robot-robot " + one(c.self);
  if (has_scene_pairs_) text += ", robot-obstacle " + one(c.scene);
  return text;
}

void ReachController::ReportGoals(std::ostream& out) const {
  for (size_t k = 0; k < ngoals_; ++k) {
    const GoalReport& g = reports_[k];
    out << "reach: goal " << k + 1 << "/" << ngoals_ << " (" << Label(k) << "): ";
    if (!g.planned) {
      out << "not reached (the run ended first)\n";
      continue;
    }
    if (!g.solved) {
      out << "planning failed: " << g.reason << "\n";
      continue;
    }
    out << Fmt("planned in %.1f + %.1f ms, path %.3f rad, ", 1e3 * g.plan_time, 1e3 * g.simplify_time, g.length)
        << g.waypoints << Fmt(" waypoints, %.2f s; planned clearance %.1f mm", g.duration, 1e3 * g.closest.distance)
        << " (" << g.closest.a << " / " << g.closest.b << ")";
    if (g.row_end > g.row_begin) {
      out << "; measured clearance " << Describe(ClearanceOfRows(g.row_begin, g.row_end));
    }
    if (g.done) {
      double worst = 0;
      for (double e : g.final_error) worst = std::max(worst, std::abs(e));
      out << Fmt("; final error %.4f rad", worst);
    } else {
      out << "; not done when the run ended";
    }
    out << "\n";
  }
}

void ReachController::report(std::ostream& out) const {
  BalanceController::report(out);
  const int state = plan_state_.load();
  out << "reach: group";
  for (const auto& n : group_.names) out << " " << n;
  out << "\n";
  if (channel_ && ngoals_ == 0) {
    out << "reach: no live goal came (live: " << channel_->received() << " received, "
        << channel_->refused() << " refused)\n";
    return;
  }
  if (state == kIdle || state == kRequested) {
    out << "reach: no plan made (the run ended " << (state == kIdle ? "before the start" : "while planning")
        << ")\n";
    return;
  }
  if (!reach_.scene.empty())
    out << "reach: scene " << reach_.scene_file << ": " << reach_.scene.size()
        << " static obstacles placed from the estimated base pose at the plan's request: "
        << Fmt("base at (%.3f, %.3f, %.3f) m (estimator), ", request_p_WB_.x(), request_p_WB_.y(), request_p_WB_.z())
        << Fmt("the soles' midpoint at (%.3f, %.3f) m in the scene (keyframe ", X_WE_.translation().x(), X_WE_.translation().y())
        << reach_.scene_keyframe << "), "
        << Fmt("tilt %.2f deg\n", 180 / M_PI * std::acos(std::clamp(
                                       (request_quat_WB_.normalized().toRotationMatrix() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0)));
  if (!reach_.plan_log.empty())
    out << "reach: plan log " << reach_.plan_log << (log_error_.empty() ? "" : " NOT written: " + log_error_) << "\n";
  const planning::PlanResult& p = result_;
  if (!p.solved) {
    out << "reach: planning failed: " << p.reason << " (" << p.evaluations << " posture checks, "
        << Fmt("%.1f ms)\n", 1e3 * p.plan_time);
    return;
  }
  out << "reach: planned in " << Fmt("%.1f ms (RRTConnect) + %.1f ms (simplification), ", 1e3 * p.plan_time, 1e3 * p.simplify_time)
      << p.evaluations << " posture checks; path " << Fmt("%.3f rad (raw %.3f), ", p.length, p.raw_length)
      << p.waypoints.size() << " waypoints, " << Fmt("%.2f s; planned clearance %.1f mm", path_.duration(), 1e3 * p.closest.distance)
      << " (" << p.closest.a << " / " << p.closest.b << ")\n";
  if (ngoals_ > 0) {
    const GoalReport& g = reports_[current_];
    if (g.blended)
      out << "reach: timing: blended at the waypoints (the arm does not stop at them; the corners "
          << Fmt("cut by at most %.3f rad), the blended path keeps %.1f mm", MaxCornerCut(), 1e3 * g.blended_closest.distance)
          << " (" << g.blended_closest.a << " / " << g.blended_closest.b << ")\n";
    else if (g.waypoints > 2)
      out << "reach: timing: rest to rest at each waypoint (" << g.stops << ")\n";
  }
  out << "reach: the straight joint-space line would " << (straight_.valid ? "keep " : "come to ")
      << Fmt("%.1f mm", 1e3 * straight_.distance) << " (" << straight_.a << " / " << straight_.b << ")\n";
  if (phase_reach_ != Phase::kPlanning)
    out << "reach: the motion began " << Fmt("%.3f s (producer time) after the plan was asked at %.3f s", motion_start_ - request_time_, request_time_)
        << " (the robot stands meanwhile; a simulation faster than real time runs on while the plan is made)\n";
  const planning::Verdict& c = MeasuredClearance();
  if (log_rows_ > 0)
    out << "reach: measured clearance along the executed motion " << Fmt("%.1f mm", 1e3 * c.distance)
        << " (" << c.a << " / " << c.b << ", " << log_rows_ << " measured postures"
        << (log_dropped_ ? ", some not recorded" : "") << Fmt("; the planner keeps %.1f mm): ", 1e3 * check_->required())
        << Describe(ClearanceOfRows(0, log_rows_)) << "\n";
  if (ngoals_ > 1 || channel_) ReportGoals(out);
  if (channel_)
    out << "reach: live: " << channel_->received() << " received, " << channel_->refused()
        << " refused, " << channel_->taken() << " taken\n";
  if (phase_reach_ == Phase::kDone) {
    double worst = 0;
    int at = 0;
    for (int i = 0; i < group_.size(); ++i)
      if (std::abs(final_error_[i]) > worst) worst = std::abs(final_error_[i]), at = i;
    out << "reach: final tracking error " << Fmt("%.4f rad", worst) << " (" << group_.names[at]
        << ") after " << Fmt("%.2f s of hold (tolerance %.3f rad)\n", reach_.hold, reach_.tolerance);
    for (const HandGoal& hand : last_hands_)
      out << "reach: the hand (" << hand.site << ") measured "
          << Fmt("%.1f mm from its goal (%.3f, %.3f, %.3f) m in the base frame, by the model's kinematics\n",
                 1e3 * HandError(hand), hand.p_B.x(), hand.p_B.y(), hand.p_B.z());
  }
}

std::string ReachController::failure() const {
  if (std::string f = BalanceController::failure(); !f.empty()) return f;
  if (!log_error_.empty()) return "--plan-log: " + log_error_;
  const int state = plan_state_.load();
  if (state == kUnsolved) return "planning failed: " + result_.reason;
  if (channel_ && ngoals_ == 0) return "";  // live, and no goal came: it stood
  if (phase_reach_ != Phase::kDone || current_ + 1 < ngoals_)
    return "the run ended before the motion and its hold were done (give the run more time)";
  for (size_t k = 0; k < ngoals_; ++k) {
    double worst = 0;
    for (double e : reports_[k].final_error) worst = std::max(worst, std::abs(e));
    if (!(worst <= reach_.tolerance))
      return "final tracking error " + Fmt("%.4f rad", worst) + " exceeds --tolerance" +
             (ngoals_ > 1 ? " at goal " + std::to_string(k + 1) + " (" + Label(k) + ")" : "");
  }
  return "";
}

}  // namespace ohrp::controllers
