// reach's plan for the viewer's reach overlay (docs/view.md, "The reach plan in 3D"): a run
// folder's plan.csv (reach --plan-log: a "# reach plan: ..." line, then goal,kind,t,JOINT...
// rows, t from each goal's motion start; docs/planning.md) read back, each goal placed on the
// log's time line where its measured motion matches the log's joint angles, and the planned
// motion drawn as the paths of the group's hands (the origins of the group's outermost bodies)
// through the scene's kinematics, the rest of the robot as the log has it when the motion
// begins. Units: SI (m, s, rad).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ohrp::view {

struct ReachPlanRow {
  double t = 0;                 // [s] from the goal's motion start
  std::vector<double> q;        // the group's joints, in the file's column order [rad or m]
};

struct ReachPlanGoal {
  int goal = 0;                 // 1, 2, ...
  bool solved = false;          // the first line's word for it
  std::vector<ReachPlanRow> waypoints, planned, measured;
};

// plan.csv as read: the group's joint names and the goals in order
struct ReachPlanLog {
  std::vector<std::string> joints;
  std::vector<ReachPlanGoal> goals;
};

// Reads `path`; false with `*error` "PATH:LINE: what" (no header, a row of the wrong width or
// with a value that is not a number, an unknown kind, no rows).
bool ReadReachPlanLog(const std::string& path, ReachPlanLog* out, std::string* error);

// Where the measured rows `m` (t from the motion start) lie on a log's time line: the start time
// T in `times` [s] that minimises the squared difference of m's values and `q_at(T + t)` (the
// log's group joints, interpolated) over up to 32 of m's rows spread over the motion. NaN when
// `m` or `times` is empty.
double AlignMotion(const std::vector<ReachPlanRow>& m, const std::vector<double>& times,
                   const std::function<std::vector<double>(double)>& q_at);

// The outermost bodies of the joints `joint_bodies` (MuJoCo body ids of the group's joints): those
// that are no other's ancestor, in the order given; `parent` is the model's body_parentid.
std::vector<int> TipBodies(const std::vector<int>& joint_bodies, const int* parent);

}  // namespace ohrp::view
