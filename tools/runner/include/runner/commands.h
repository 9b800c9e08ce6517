// The command lines of a run's processes (sim_host and each controller), built from a scenario,
// and the placeholders their arguments may hold.
//
// Placeholders: a scenario's controller `args` and its `sim_args` may name the run's output
// folder as `{out}` (e.g. `--log, "{out}/walk.csv"`); it is replaced by the folder's absolute
// path before the process starts. Any other `{...}` is refused when the scenario is read
// (UnknownPlaceholder), so a typo such as `{output}` does not reach a process as text.
#pragma once

#include <string>
#include <vector>

#include "runner/scenario.h"

namespace ohrp::runner {

// the output folder's placeholder
inline constexpr char kOutPlaceholder[] = "{out}";

// "" when every `{...}` in `arg` is a known placeholder (only `{out}`); otherwise what is wrong
// and what would work, naming the first unknown one. A `{` without a closing `}` is plain text.
std::string UnknownPlaceholder(const std::string& arg);

// `arg` with every `{out}` replaced by `out_dir` (used as given: pass an absolute path).
std::string ExpandPlaceholders(const std::string& arg, const std::string& out_dir);

// Writes the scenario's joint_params (per joint armature, damping, frictionloss) to `path`, the
// file SimHostCommand names in the run folder (joint_params.yaml) for sim_host's --joint-file
// (robot_model/joint_params.h). False with `*error` when it cannot be written.
bool WriteJointParams(const Scenario& s, const std::string& path, std::string* error);

// sim_host's command line for scenario `s`: the program `sim_host` (a path), the resolved
// `scene`, the segment, the log and summary in `out_dir` (absolute), a self_collisions check's
// effect, the scenario's keys that are sim_host options (from their table, cli/host_options.h:
// the run's settings, its pushes, its effects), the soft soles' parameters, the joints' file,
// and last its `sim_args` with placeholders expanded (so they win).
std::vector<std::string> SimHostCommand(const Scenario& s, const std::string& sim_host,
                                        const std::string& scene, const std::string& segment,
                                        const std::string& out_dir);

// A controller's command line: `program` (a path), --segment, --attach-timeout 10, then the
// scenario's `args` with placeholders expanded (`out_dir` absolute).
std::vector<std::string> ControllerCommand(const ControllerSpec& spec, const std::string& program,
                                           const std::string& segment, const std::string& out_dir);

}  // namespace ohrp::runner
