// The joint group: names to ids and limits.
#include "planning/joint_group.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace ohrp::planning {

bool MakeJointGroup(const collision::RobotGeometry& robot, const std::vector<std::string>& names,
                    JointGroup* group, std::string* error) {
  *group = JointGroup();
  if (names.empty()) {
    *error = "the joint group is empty: name the joints the plan moves";
    return false;
  }
  for (const std::string& n : names) {
    const int id = collision::FindJoint(robot, n);
    if (id < 0) {
      std::string known;
      for (int j = 0; j < collision::NumJoints(robot); ++j)
        known += (j ? ", " : "") + collision::JointName(robot, j);
      *error = "joint '" + n + "' is not one of the robot's (" + known + ")";
      return false;
    }
    if (std::find(group->ids.begin(), group->ids.end(), id) != group->ids.end()) {
      *error = "joint '" + n + "' is named twice in the group";
      return false;
    }
    group->names.push_back(n);
    group->ids.push_back(id);
    group->lo.push_back(robot.q_min[id]);
    group->hi.push_back(robot.q_max[id]);
  }
  return true;
}

void GroupValues(const JointGroup& group, std::span<const double> posture, std::span<double> values) {
  for (int i = 0; i < group.size(); ++i) values[i] = posture[group.ids[i]];
}

void SetGroupValues(const JointGroup& group, std::span<const double> values, std::span<double> posture) {
  for (int i = 0; i < group.size(); ++i) posture[group.ids[i]] = values[i];
}

std::string OutsideLimits(const JointGroup& group, std::span<const double> values) {
  for (int i = 0; i < group.size(); ++i) {
    const double v = values[i];
    if (std::isfinite(v) && v >= group.lo[i] && v <= group.hi[i]) continue;
    char text[256];
    if (!std::isfinite(v))
      std::snprintf(text, sizeof text, "%s is not a number", group.names[i].c_str());
    else
      std::snprintf(text, sizeof text, "%s = %.4f is outside its limits [%.4f, %.4f] by %.4f",
                    group.names[i].c_str(), v, group.lo[i], group.hi[i],
                    v < group.lo[i] ? group.lo[i] - v : v - group.hi[i]);
    return text;
  }
  return "";
}

}  // namespace ohrp::planning
