// The refinement's simulations as sweeps (ohrp::sweep): one stage, one sweep (see identify.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "identify/identify.h"

namespace ohrp::identify {

// Runs the experiment (o.scenario) once per (K [N/m], D [s/m]) of `kd` as one sweep named
// identify_<stage> of contact_params.stiffness and .damping zipped, with o.executor, in the sweep
// folder o.out_dir/<stage> (its sweep file <stage>.yaml, sweep.csv and table.md there too).
// `variant_dirs` gets each run's variant folder (its data log: run/log.csv), in the order of
// `kd`; `record` the stage (name, folder, variants, wall time, Slurm job). False with *error
// naming the run that gave no log and why (its status and logs).
bool SimulateStage(const IdentifyOptions& o, const std::string& stage,
                   const std::vector<std::pair<double, double>>& kd,
                   std::vector<std::string>* variant_dirs, nlohmann::json* record, std::string* error);

}  // namespace ohrp::identify
