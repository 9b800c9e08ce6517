// A joint group: the joints a plan moves (an arm, both arms, an arm and the waist), by name, with
// their joint ids and limits in a robot's collision geometry (collision/geometry.h). The other
// joints of a posture stay where they are.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "collision/geometry.h"

namespace ohrp::planning {

struct JointGroup {
  std::vector<std::string> names;  // in the order of the group's values
  std::vector<int> ids;            // joint ids in the geometry (actuated, then passive)
  std::vector<double> lo, hi;      // the model's limits [rad, m]
  int size() const { return static_cast<int>(ids.size()); }
};

// The group of `names` in `robot`. False with `*error` for an empty list, an unknown joint
// (with the joints there are) or a joint named twice.
bool MakeJointGroup(const collision::RobotGeometry& robot, const std::vector<std::string>& names,
                    JointGroup* group, std::string* error);

// The group's values of a whole posture, and a whole posture with the group's values written in.
void GroupValues(const JointGroup& group, std::span<const double> posture, std::span<double> values);
void SetGroupValues(const JointGroup& group, std::span<const double> values, std::span<double> posture);

// "" when every value is finite and inside its joint's limits, else which one is not and by how
// much ("LARM_ELBOW = 0.500 rad is outside its limits [-2.618, 0.175] by 0.325")
std::string OutsideLimits(const JointGroup& group, std::span<const double> values);

}  // namespace ohrp::planning
