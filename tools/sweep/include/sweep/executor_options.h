// The executor's command-line options, shared by every program that runs sweeps (ohrp_sweep,
// ohrp_identify): --jobs, --slurm, --partition, --time, --max-running, --sbatch-arg, --poll,
// all filling one Executor (sweep.h). docs/sweep.md describes them.
#pragma once

#include "sweep/sweep.h"

namespace CLI {
class App;
}

namespace ohrp::sweep {

// Adds the options to `app`; after parsing, `*ex` holds them (--slurm sets kind to kSlurm).
// `what` names the runs in the help ("variants", "simulations").
void AddExecutorOptions(CLI::App* app, Executor* ex, const std::string& what = "variants");

}  // namespace ohrp::sweep
