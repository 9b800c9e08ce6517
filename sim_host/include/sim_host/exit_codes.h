// sim_host's exit codes (docs/architecture.md "Faults and exit codes of sim_host"), header-only
// so that the runner can read a run's outcome without linking sim_host (it gets this folder
// through ohrp::sim_step).
#pragma once

#include "robot_model/output_file.h"

namespace ohrp::sim {

// exit codes of sim_host
inline constexpr int kExitOk = 0;
inline constexpr int kExitUsage = 2;           // bad option, model, keyframe or segment
inline constexpr int kExitMujocoError = 3;
inline constexpr int kExitDiverged = 4;
inline constexpr int kExitControllerLost = 5;  // lost (or never got) a controller, policy "end"
inline constexpr int kExitFell = 6;            // the robot fell (sim_host/fall.h), with --on-fall
                                               // end or continue; 4, 5 and 3 take precedence
inline constexpr int kExitOutputFailed = model::kExitOutputFailed;  // 9: the data log or the
                                               // summary could not be written completely
inline constexpr int kExitInterrupted = 130;   // SIGINT / SIGTERM: clean shutdown

}  // namespace ohrp::sim
