// reach's goals as text (the command line's --goal-joints and --goal-pose, the live channel's
// `joints` and `pose` lines): controllers/reach_goals.h.
#include <cmath>
#include <sstream>

#include "cli/command_line.h"
#include "controllers/reach_goals.h"

namespace ohrp::controllers {

bool ParseJointsGoal(const std::vector<std::string>& items, const std::string& what,
                     std::vector<std::pair<std::string, double>>* goals, std::string* error) {
  for (const std::string& item : items) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == item.size()) {
      *error = what + ": '" + item + "' is not NAME=VALUE (a joint name and radians)";
      return false;
    }
    std::istringstream in(item.substr(eq + 1));
    double v = NAN;
    std::string rest;
    if (!(in >> v) || (in >> rest) || !std::isfinite(v)) {
      *error = what + ": '" + item + "': the value is not a finite number of radians";
      return false;
    }
    goals->emplace_back(item.substr(0, eq), v);
  }
  return true;
}

namespace {

// one hand: "SITE,X,Y,Z[,ROLL,PITCH,YAW]" (split at the commas); false with `*error`
bool ParseHandPose(const std::vector<std::string>& items, const std::string& what, HandGoal* hand,
                   std::string* error) {
  if (items.size() != 4 && items.size() != 7) {
    std::string given;
    for (const std::string& i : items) given += (given.empty() ? "" : ",") + i;
    *error = what + ": '" + given +
             "': give SITE,X,Y,Z or SITE,X,Y,Z,ROLL,PITCH,YAW (metres, radians) for each hand";
    return false;
  }
  hand->site = items[0];
  double v[6] = {0, 0, 0, 0, 0, 0};
  for (size_t i = 1; i < items.size(); ++i) {
    std::istringstream in(items[i]);
    std::string rest;
    if (!(in >> v[i - 1]) || (in >> rest) || !std::isfinite(v[i - 1])) {
      *error = what + ": '" + items[i] + "' is not a finite number";
      return false;
    }
    const char* quantity = i <= 3 ? "height" : "angle";  // within 10 m; within a turn
    if (const std::string why = ohrp::cli::CheckPlausible(quantity, v[i - 1], what);
        !why.empty()) {
      *error = why;
      return false;
    }
  }
  hand->p_B = Eigen::Vector3d(v[0], v[1], v[2]);
  hand->orientation = items.size() == 7;
  hand->rpy = Eigen::Vector3d(v[3], v[4], v[5]);
  return true;
}

}  // namespace

bool ParseHandPoses(const std::vector<std::string>& items, const std::string& what,
                    std::vector<HandGoal>* hands, std::string* error) {
  auto number = [](const std::string& s) {
    std::istringstream in(s);
    double v = 0;
    std::string rest;
    return static_cast<bool>(in >> v) && !(in >> rest);
  };
  for (size_t i = 0; i < items.size();) {
    size_t end = i + 1;
    while (end < items.size() && number(items[end])) ++end;
    HandGoal hand;
    if (!ParseHandPose({items.begin() + i, items.begin() + end}, what, &hand, error)) return false;
    hands->push_back(hand);
    i = end;
  }
  return true;
}

}  // namespace ohrp::controllers
