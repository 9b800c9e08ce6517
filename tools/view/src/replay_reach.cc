// The replayed run's reach plan (plan.csv) as hand paths in the world (source.h, LoadReach;
// view/reach_plan.h).
#include <algorithm>
#include <cmath>
#include <fstream>

#include "view/reach_plan.h"
#include "view/source.h"

namespace ohrp::view {
namespace {

constexpr size_t kPathPoints = 200;  // a goal's path is drawn with at most this many points

}  // namespace

void ReplaySource::LoadReach(const std::string& run_dir) {
  const std::string path = run_dir + "/plan.csv";
  if (!std::ifstream(path)) {
    reach_ = {{"note", "no plan.csv in the run folder (reach --plan-log)"}};
    return;
  }
  ReachPlanLog plan;
  std::string error;
  if (!ReadReachPlanLog(path, &plan, &error)) {
    reach_ = {{"note", error}};
    return;
  }
  // the group's joints among the log's, and their bodies
  const model::RobotMap& robot = geometry_->robot();
  const mjModel* m = geometry_->model();
  std::vector<int> ids, bodies;
  for (const std::string& name : plan.joints) {
    const auto it = std::find_if(robot.joints.begin(), robot.joints.end(),
                                 [&](const auto& j) { return j.name == name; });
    if (it == robot.joints.end() || q_col_[it - robot.joints.begin()] < 0) {
      reach_ = {{"note", "plan.csv's joint " + name + " is not in the log"}};
      return;
    }
    ids.push_back(static_cast<int>(it - robot.joints.begin()));
    bodies.push_back(m->jnt_bodyid[it->joint_id]);
  }
  const std::vector<int> tips = TipBodies(bodies, m->body_parentid);
  // the group's logged joints at time t, interpolated as StateAt does (only those columns)
  const std::vector<double>& times = log_.col(time_col_);
  std::vector<double> q(ids.size());
  auto group_q = [&](double t) {
    const size_t next = std::lower_bound(times.begin(), times.end(), t) - times.begin();
    const size_t hi = std::min(next, times.size() - 1), lo = hi > 0 ? hi - 1 : 0;
    const double span = times[hi] - times[lo];
    const double u = span > 0 ? std::clamp((t - times[lo]) / span, 0.0, 1.0) : 1.0;
    for (size_t i = 0; i < ids.size(); ++i) {
      const std::vector<double>& c = log_.col(q_col_[ids[i]]);
      q[i] = c[lo] + u * (c[hi] - c[lo]);
    }
    return q;
  };
  // each goal: where its motion began on the log's time line, then its planned motion from the
  // posture the robot had then
  nlohmann::json goals = nlohmann::json::array();
  std::lock_guard lock(mutex_);
  for (const ReachPlanGoal& g : plan.goals) {
    if (g.planned.empty() || g.measured.empty()) continue;  // not solved, or never moved
    const double t_start = AlignMotion(g.measured, times, group_q);
    if (!std::isfinite(t_start)) continue;
    const RobotState at_start = StateAt(t_start);
    auto hands = [&](const std::vector<ReachPlanRow>& rows, size_t most) {
      nlohmann::json per_tip = nlohmann::json::array();
      for (size_t k = 0; k < tips.size(); ++k) per_tip.push_back(nlohmann::json::array());
      const size_t stride = std::max<size_t>(1, (rows.size() + most - 1) / most);
      for (size_t r = 0; r < rows.size(); r += std::min(stride, std::max<size_t>(1, rows.size() - 1 - r))) {
        RobotState s = at_start;
        for (size_t i = 0; i < ids.size(); ++i) s.q[ids[i]] = rows[r].q[i];
        geometry_->Poses(s);
        for (size_t k = 0; k < tips.size(); ++k) {
          const std::array<double, 3> p = geometry_->BodyOrigin(tips[k]);
          per_tip[k].push_back({p[0], p[1], p[2]});
        }
        if (r + 1 == rows.size()) break;
      }
      return per_tip;
    };
    goals.push_back({{"goal", g.goal}, {"solved", g.solved}, {"t_start", t_start},
                     {"t_end", t_start + g.measured.back().t},
                     {"paths", hands(g.planned, kPathPoints)}, {"waypoints", hands(g.waypoints, 64)}});
  }
  nlohmann::json names = nlohmann::json::array();
  for (int b : tips) names.push_back(mj_id2name(m, mjOBJ_BODY, b) ? mj_id2name(m, mjOBJ_BODY, b) : "?");
  if (goals.empty()) reach_ = {{"note", "plan.csv has no goal that moved"}};
  else reach_ = {{"goals", goals}, {"hands", names}};
}

}  // namespace ohrp::view
