// reach's goals: the group and each goal's joint values, checked before anything attaches
// (the command line's one goal, or a goals file's goals in sequence: controllers/reach_goals.h).
#include <algorithm>

#include "controllers/reach.h"

namespace ohrp::controllers {

ConfigStatus ReachController::ResolveGoals(const std::vector<double>& stance) {
  const ReachOptions& o = reach_;
  const bool file = !o.goals.goals.empty();
  std::vector<GoalSpec> specs = o.goals.goals;
  if (!file) {  // the command line's goal as a list of one
    GoalSpec one;
    one.joints = o.goal_joints;
    one.hands = o.hands;
    specs.push_back(one);
  }
  // "--goal-joints: ", "--group: ", or "FILE:LINE: KEY: "
  auto where = [&](const GoalSpec& g, const char* key) {
    if (file) return o.goals.path + ":" + std::to_string(g.line) + ": " + key + ": ";
    return std::string(g.hands.empty() ? "--goal-joints" : "--group") + ": ";
  };
  auto bad = [](const std::string& what) { return ConfigStatus::Fail(ConfigError::kOption, what); };
  // the group: --group, the file's group, or the (first) joints goal's names
  std::vector<std::string> names = file ? o.goals.group : o.group;
  if (names.empty())
    for (const auto& [name, value] : specs[0].joints) names.push_back(name);
  std::string error;
  if (!planning::MakeJointGroup(file_.robot, names, &group_, &error))
    return bad((file ? o.goals.path + ": group: " : where(specs[0], "")) + error);
  check_ = planning::PostureCheck::Create(file_, o.boxes, group_, o.clearance, &error);
  if (!check_) return ConfigStatus::Fail(ConfigError::kFile, o.collision_file + ": " + error);
  // each goal from the previous one's values (the first from the stance)
  std::vector<double> values(group_.size());
  planning::GroupValues(group_, stance, values);
  for (const GoalSpec& g : specs) {
    if (!g.hands.empty()) {
      // the IK from the stance pose, as --goal-pose (from the previous goal it may stall)
      if (ConfigStatus s = GoalFromHandPose(*kin_ik_, group_, g.hands, stance, &values); !s.ok())
        return file ? bad(where(g, "pose") + s.message.substr(s.message.rfind("--goal-pose: ", 0) == 0 ? 13 : 0)) : s;
    } else {
      for (const auto& [name, value] : g.joints) {
        const auto it = std::find(group_.names.begin(), group_.names.end(), name);
        if (it == group_.names.end())
          return bad(where(g, "joints") + name + " is not in the group (" + std::to_string(group_.size()) +
                     " joints from " + group_.names[0] + ")");
        values[it - group_.names.begin()] = value;
      }
      if (!(error = planning::OutsideLimits(group_, values)).empty()) return bad(where(g, "joints") + error);
    }
    std::vector<double> posture = stance;
    planning::SetGroupValues(group_, values, posture);
    const planning::Verdict v = check_->Evaluate(posture);
    if (!v.valid)
      return bad(where(g, g.hands.empty() ? "joints" : "pose") + "the goal is in collision in the stance pose: " +
                 check_->Describe(v));
    goals_.push_back(values);
    holds_.push_back(g.hold >= 0 ? g.hold : o.hold);
    labels_.push_back(file ? o.goals.path + ":" + std::to_string(g.line) : "the goal");
  }
  goal_ = goals_[0];
  last_hands_ = specs.back().hands;
  has_scene_pairs_ = !o.boxes.empty() || !o.scene.empty();
  return ConfigStatus::Ok();
}

}  // namespace ohrp::controllers
