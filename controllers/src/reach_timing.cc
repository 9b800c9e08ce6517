// reach's timing of a solved plan (controllers/reach.h, TimeThePath; planning/timed_path.h):
// blended at the waypoints (the arm does not stop at them) when the blended path, whose corners
// are cut, is checked again at the planner's resolution and keeps the planner's clearance;
// else rest to rest along the checked polyline.
#include <algorithm>
#include <cmath>

#include "controllers/reach.h"

namespace ohrp::controllers {

void ReachController::TimeThePath() {
  GoalReport& g = reports_[current_];
  std::string error;
  g.blended = false;
  g.stops = reach_.stop_at_waypoints ? "--stop-at-waypoints" : "";
  if (!reach_.stop_at_waypoints && path_.Build(result_.waypoints, v_max_, a_max_, &error, true) &&
      path_.blended()) {
    // the blended path at the planner's resolution: each sample at most `resolution` of
    // joint-space distance from the last at the joints' speed limits
    double speed = 0;
    for (double v : v_max_) speed += v * v;
    const double dt = reach_.plan.resolution / std::max(1e-9, std::sqrt(speed));
    std::vector<double> posture = request_, values(group_.size());
    planning::Verdict closest;
    closest.distance = INFINITY;
    for (double t = 0;; t = std::min(t + dt, path_.duration())) {
      path_.Sample(t, values.data(), nullptr, nullptr);
      planning::SetGroupValues(group_, values, posture);
      const planning::Verdict v = check_->Evaluate(posture);
      if (v.distance < closest.distance) closest = v;
      if (t >= path_.duration()) break;
    }
    if (closest.distance >= check_->required()) {
      g.blended = true;
      g.blended_closest = closest;
      return;
    }
    g.stops = "the blended path comes to " + check_->Describe(closest);
  }
  if (!path_.Build(result_.waypoints, v_max_, a_max_, &error, false)) {
    result_.solved = false;
    result_.reason = "timing: " + error;
  }
}

double ReachController::MaxCornerCut() const {
  double cut = 0;
  for (int k = 1; k + 1 < static_cast<int>(result_.waypoints.size()); ++k) cut = std::max(cut, path_.CornerCut(k));
  return cut;
}

}  // namespace ohrp::controllers
