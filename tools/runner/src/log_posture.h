// A logged row of the simulated state put back into a MuJoCo model (the checks that replay the
// logged motion through the scene: vision_checks.cc, obstacle_checks.cc).
#pragma once

#include <mujoco/mujoco.h>

#include <string>

#include "datalog/table.h"

namespace ohrp::runner {

// Sets d->qpos from row `row` of the data log: a free joint from base_x..base_qz (its
// quaternion normalised), each hinge and slide from q_NAME. A hinge or slide the log lacks keeps
// its value when `all_joints` is false (a passive joint not logged), else is an error. `*joints`
// (when given) counts the hinges and slides set. False with `*error` naming the missing column.
bool PostureFromLogRow(const mjModel* m, mjData* d, const datalog::Table& log, size_t row,
                       bool all_joints, int* joints, std::string* error);

}  // namespace ohrp::runner
