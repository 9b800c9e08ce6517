// reach's goals file (reach --goals FILE.yaml, docs/planning.md): several goals reached in
// sequence, each planned from the posture the previous one left, executed and held.
//
//   group: [LARM_SHOULDER_P, LARM_SHOULDER_R, ...]   # the joints the plans move; optional when
//                                                    # the first goal is joints (then its names)
//   goals:
//     - joints: {LARM_SHOULDER_P: -1.1, LARM_ELBOW: -0.3}   # radians; the group's joints not
//       hold: 1.0                                          # named keep the previous goal's value
//     - pose: {site: lhsensor, position: [0.2, -0.05, 0.25], rpy: [0, -1.57, 0]}
//                                                    # base frame [m, rad]; rpy optional
//     - pose: [{site: lhsensor, position: [...]}, {site: rhsensor, position: [...]}]
//                                                    # both hands: one pose per limb
//
// `hold` [s] is optional (the command line's --hold). A bad file is refused with
// "FILE:LINE: KEY: what" (a missing or unknown key, a value that is not a number, no goals).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "controllers/reach.h"

namespace ohrp::controllers {

// Reads and checks `path` (the shape above); false with `*error` "PATH:LINE: KEY: what".
bool ReadGoalsFile(const std::string& path, GoalsFile* out, std::string* error);

// A joints goal "NAME=VALUE,..." (`items`: split at the commas) into pairs [rad]; false with
// `*error` "WHAT: 'ITEM': why" (`what`: the option or command it came from).
bool ParseJointsGoal(const std::vector<std::string>& items, const std::string& what,
                     std::vector<std::pair<std::string, double>>* goals, std::string* error);
// Hand poses "SITE,X,Y,Z[,ROLL,PITCH,YAW]" (`items`: split at the commas, several hands one
// after another: a word that is not a number begins the next) [m, rad]; false with `*error`.
bool ParseHandPoses(const std::vector<std::string>& items, const std::string& what,
                    std::vector<HandGoal>* hands, std::string* error);

}  // namespace ohrp::controllers
