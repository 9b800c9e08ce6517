// reach's plan log for the viewer (view/reach_plan.h).
#include "view/reach_plan.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

namespace ohrp::view {
namespace {

std::vector<std::string> Split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string item; std::getline(in, item, ',');) out.push_back(item);
  return out;
}

bool Number(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && std::isfinite(*v);
}

}  // namespace

bool ReadReachPlanLog(const std::string& path, ReachPlanLog* out, std::string* error) {
  *out = ReachPlanLog();
  std::ifstream in(path);
  if (!in) return *error = path + ": cannot read it", false;
  std::string line, first;
  int n = 0;
  auto fail = [&](const std::string& what) {
    *error = path + ":" + std::to_string(n) + ": " + what;
    return false;
  };
  std::vector<bool> solved;
  while (std::getline(in, line)) {
    ++n;
    if (line.empty()) continue;
    if (line[0] == '#') {  // "# reach plan: goal 1: solved; goal 2: not solved: ..."
      for (size_t at = 0; (at = line.find("goal ", at)) != std::string::npos; at += 5)
        solved.push_back(line.compare(line.find(": ", at) + 2, 6, "solved") == 0);
      continue;
    }
    const std::vector<std::string> items = Split(line);
    if (out->joints.empty()) {
      if (items.size() < 4 || items[0] != "goal" || items[1] != "kind" || items[2] != "t")
        return fail("the header is not goal,kind,t,JOINT... (a reach --plan-log file)");
      out->joints.assign(items.begin() + 3, items.end());
      continue;
    }
    if (items.size() != out->joints.size() + 3)
      return fail(std::to_string(items.size()) + " values, the header has " + std::to_string(out->joints.size() + 3));
    double goal = 0;
    ReachPlanRow row;
    row.q.resize(out->joints.size());
    if (!Number(items[0], &goal) || goal < 1 || goal != std::floor(goal)) return fail("goal '" + items[0] + "' is not 1, 2, ...");
    if (!Number(items[2], &row.t)) return fail("t '" + items[2] + "' is not a number");
    for (size_t i = 0; i < row.q.size(); ++i)
      if (!Number(items[3 + i], &row.q[i])) return fail(out->joints[i] + " '" + items[3 + i] + "' is not a number");
    while (static_cast<int>(out->goals.size()) < goal) {
      out->goals.emplace_back();
      out->goals.back().goal = static_cast<int>(out->goals.size());
    }
    ReachPlanGoal& g = out->goals[static_cast<size_t>(goal) - 1];
    if (items[1] == "waypoint") g.waypoints.push_back(row);
    else if (items[1] == "planned") g.planned.push_back(row);
    else if (items[1] == "measured") g.measured.push_back(row);
    else return fail("kind '" + items[1] + "' is not waypoint, planned or measured");
  }
  if (out->joints.empty()) return fail("no header (goal,kind,t,JOINT...)");
  if (out->goals.empty()) return fail("no rows");
  for (size_t k = 0; k < out->goals.size() && k < solved.size(); ++k) out->goals[k].solved = solved[k];
  return true;
}

double AlignMotion(const std::vector<ReachPlanRow>& m, const std::vector<double>& times,
                   const std::function<std::vector<double>(double)>& q_at) {
  if (m.empty() || times.empty()) return NAN;
  const size_t samples = std::min<size_t>(32, m.size());
  double best = NAN, best_cost = std::numeric_limits<double>::infinity();
  for (double T : times) {
    if (T + m.back().t > times.back() + 1e-9) break;  // the motion would run past the log
    double cost = 0;
    for (size_t k = 0; k < samples && cost < best_cost; ++k) {
      const ReachPlanRow& r = m[k * (m.size() - 1) / std::max<size_t>(1, samples - 1)];
      const std::vector<double> q = q_at(T + r.t);
      for (size_t i = 0; i < r.q.size() && i < q.size(); ++i) cost += (q[i] - r.q[i]) * (q[i] - r.q[i]);
    }
    if (cost < best_cost) best_cost = cost, best = T;
  }
  return best;
}

std::vector<int> TipBodies(const std::vector<int>& joint_bodies, const int* parent) {
  std::vector<int> tips;
  for (int b : joint_bodies) {
    bool ancestor = false;  // of another joint's body
    for (int c : joint_bodies)
      for (int a = parent[c]; a > 0 && !ancestor && c != b; a = parent[a]) ancestor = a == b;
    if (!ancestor && std::find(tips.begin(), tips.end(), b) == tips.end()) tips.push_back(b);
  }
  return tips;
}

}  // namespace ohrp::view
