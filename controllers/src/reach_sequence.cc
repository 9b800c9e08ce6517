// reach's goals: the group and each goal's joint values, checked before anything attaches
// (the command line's one goal, or a goals file's goals in sequence: controllers/reach_goals.h),
// and the live goals' channel (controllers/reach_live.h), checked the same way on its thread.
#include <algorithm>
#include <unistd.h>

#include "controllers/reach.h"
#include "controllers/reach_live.h"

namespace ohrp::controllers {

bool ReachController::ResolveGoal(model::Kinematics& kin, planning::PostureCheck& check,
                                  const GoalSpec& g, std::vector<double>* values, std::string* key,
                                  std::string* what, bool* ik) const {
  *ik = false;
  if (!g.hands.empty()) {
    *key = "pose";
    // the IK from the stance pose, as --goal-pose (from the previous goal it may stall)
    if (ConfigStatus s = GoalFromHandPose(kin, group_, g.hands, stance_, values); !s.ok()) {
      *ik = true;
      *what = s.message.substr(s.message.rfind("--goal-pose: ", 0) == 0 ? 13 : 0);
      return false;
    }
  } else {
    *key = "joints";
    for (const auto& [name, value] : g.joints) {
      const auto it = std::find(group_.names.begin(), group_.names.end(), name);
      if (it == group_.names.end()) {
        *what = name + " is not in the group (" + std::to_string(group_.size()) + " joints from " +
                group_.names[0] + ")";
        return false;
      }
      (*values)[it - group_.names.begin()] = value;
    }
    if (!(*what = planning::OutsideLimits(group_, *values)).empty()) return false;
  }
  std::vector<double> posture = stance_;
  planning::SetGroupValues(group_, *values, posture);
  const planning::Verdict v = check.Evaluate(posture);
  if (!v.valid) {
    *what = "the goal is in collision in the stance pose: " + check.Describe(v);
    return false;
  }
  return true;
}

ConfigStatus ReachController::ResolveGoals(const std::vector<double>& stance) {
  const ReachOptions& o = reach_;
  stance_ = stance;
  const bool file = !o.goals.goals.empty();
  std::vector<GoalSpec> specs = o.goals.goals;
  if (!file && (!o.goal_joints.empty() || !o.hands.empty())) {  // the command line's goal
    GoalSpec one;
    one.joints = o.goal_joints;
    one.hands = o.hands;
    specs.push_back(one);
  }
  auto bad = [](const std::string& what) { return ConfigStatus::Fail(ConfigError::kOption, what); };
  // the group: --group, the file's group, or the (first) joints goal's names
  std::vector<std::string> names = file ? o.goals.group : o.group;
  if (names.empty() && !specs.empty())
    for (const auto& [name, value] : specs[0].joints) names.push_back(name);
  const std::string group_where = file ? o.goals.path + ": group: "
                                  : !o.goal_joints.empty() ? "--goal-joints: " : "--group: ";
  std::string error;
  if (!planning::MakeJointGroup(file_.robot, names, &group_, &error)) return bad(group_where + error);
  check_ = planning::PostureCheck::Create(file_, o.boxes, group_, o.clearance, &error);
  if (!check_) return ConfigStatus::Fail(ConfigError::kFile, o.collision_file + ": " + error);
  // each goal from the previous one's values (the first from the stance)
  std::vector<double> values(group_.size());
  planning::GroupValues(group_, stance, values);
  for (const GoalSpec& g : specs) {
    std::string key, what;
    bool ik = false;
    if (!ResolveGoal(*kin_ik_, *check_, g, &values, &key, &what, &ik)) {
      if (file) return bad(o.goals.path + ":" + std::to_string(g.line) + ": " + key + ": " + what);
      return bad((ik ? "--goal-pose: " : g.hands.empty() ? "--goal-joints: " : "--group: ") + what);
    }
    goals_.push_back(values);
    holds_.push_back(g.hold >= 0 ? g.hold : o.hold);
    labels_.push_back(file ? o.goals.path + ":" + std::to_string(g.line) : "the goal");
  }
  ngoals_ = nfixed_ = goals_.size();
  if (o.live()) {  // room for the live goals, taken without allocating
    goals_.resize(nfixed_ + kMaxLiveGoals, std::vector<double>(group_.size(), 0.0));
    holds_.resize(goals_.size(), o.hold);
    labels_.resize(goals_.size(), "live");
  }
  goal_ = ngoals_ > 0 ? goals_[0] : values;
  if (!specs.empty()) last_hands_ = specs.back().hands;
  has_scene_pairs_ = !o.boxes.empty() || !o.scene.empty();
  return ConfigStatus::Ok();
}

ConfigStatus ReachController::OpenChannel() {
  std::string error;
  live_kin_ = model::Kinematics::FromModel(kin_ik_->m(), &error);
  if (live_kin_)
    live_check_ = planning::PostureCheck::Create(file_, reach_.boxes, group_, reach_.clearance, &error);
  if (!live_kin_ || !live_check_) return ConfigStatus::Fail(ConfigError::kFile, "live goals: " + error);
  // the first live goal starts from the last fixed goal, else from the stance
  std::vector<double> start(group_.size());
  if (nfixed_ > 0) start = goals_[nfixed_ - 1];
  else planning::GroupValues(group_, stance_, start);
  channel_ = std::make_unique<ReachChannel>();
  auto resolve = [this](const GoalSpec& g, std::vector<double>* values, std::string* error) {
    std::string key, what;
    bool ik = false;
    if (ResolveGoal(*live_kin_, *live_check_, g, values, &key, &what, &ik)) return true;
    *error = key + ": " + what;
    return false;
  };
  if (!channel_->Open(reach_.listen ? STDIN_FILENO : -1, reach_.socket, start, kMaxLiveGoals,
                      resolve, &error))
    return ConfigStatus::Fail(ConfigError::kOption, error);
  return ConfigStatus::Ok();
}

std::string ReachController::Label(size_t k) const {
  if (k < nfixed_ || !channel_) return labels_[k];
  return "live: " + channel_->text(k - nfixed_);
}

}  // namespace ohrp::controllers
