// ohrp_sweep: many headless runs of one scenario with parameters varied, one report.
//
// A sweep file (YAML, docs/sweep.md) names a scenario and the scenario keys to vary, by path
// (`contact_params.stiffness`, `pushes[0].impulse`, `physics_dt`, `integrator`...), each as a
// list of values or a range (from, to, steps; linear or log); the parameters combine as a grid
// (cartesian product), and a `zip` group varies its parameters together (same length). Each
// variant is the scenario with its values set, written as its own scenario file and run as one
// `ohrp_run` process with its own output folder and segment, under a wall-time limit.
//
// The work is split into stages that every executor shares:
//   LoadSweep    parse the sweep file, expand the variants, check each variant's scenario
//                with the runner's own parser (a bad value is refused before anything runs)
//   Prepare      write the sweep folder: sweep.json and variants/vNNN/{scenario.yaml,variant.json}
//   RunVariant   run one variant folder (ohrp_run under the time limit) and write status.json;
//                the local executor calls it from its workers, a Slurm array task through
//                `ohrp_sweep --task DIR` with its SLURM_ARRAY_TASK_ID
//   Gather       read every variant folder back (status.json, run/summary.json): one result per
//                variant, never lost (not run, cancelled, killed at the time limit, failed)
//   WriteReport  sweep.csv, table.md and the plots
// RunSweep(spec, executor) does all of them.
//
// From another program (e.g. an identification that refines a fit with simulations): write the
// sweep as YAML text and parse it, run it with either executor, read the results (and each
// variant's data log, `<log_dir>/run/log.csv`):
//   SweepSpec spec;
//   if (!ParseSweep(text, "tools/identify/refine.yaml", source_dir, &spec, &error)) ...;
//   const SweepOutcome o = RunSweep(spec, Executor{}, out_dir, RunContext{source_dir, bin_dir});
//   for (const VariantResult& r : o.results) ... r.status, r.checks, r.log_dir + "/run/log.csv"
#pragma once

#include <map>
#include <string>
#include <vector>

namespace ohrp::sweep {

//---------------- the sweep file ----------------

// One value of one parameter: the YAML scalar written into the scenario and shown in the
// report (numbers in their shortest form that reads back exactly).
struct Value {
  std::string text;
  bool numeric = false;
  double number = 0;  // when numeric
};

// A scenario key varied by the sweep.
struct Parameter {
  std::string key;            // path in the scenario: a.b, list[2].c
  std::vector<Value> values;
  bool log_scale = false;     // given as a log range (the plots use a log axis)
  std::string draw;           // drawn at random (draw: ...): the distribution, n and seed; "" listed
  int line = 0;               // where the sweep file gives it
};

// A figure: one check's value (or real_time_factor, wall_time) against one parameter, one
// line per combination of the other parameters.
struct PlotSpec {
  std::string check;
  std::string against;
  int line = 0;
};

// One run of the scenario: the value of each parameter (index into Parameter::values).
struct Variant {
  int id = 0;
  std::vector<int> value_index;  // one per parameter, in SweepSpec::parameters order
};

struct SweepSpec {
  std::string file;            // the sweep file
  std::string name;            // default: the file's name without .yaml
  std::string scenario_file;   // the scenario it varies (resolved path)
  std::string scenario_text;   // the scenario as read (YAML)
  std::vector<std::pair<std::string, Value>> set;  // keys set in every variant (`set:`)
  std::vector<Parameter> parameters;
  std::vector<PlotSpec> plots;
  double time_limit = 0;       // [s] wall time per variant; 0 before LoadSweep fills it in
  std::vector<Variant> variants;
  std::vector<std::string> variant_scenarios;  // the YAML of each variant's scenario
};

// Reads, expands and checks a sweep. `source_dir` is the repository root (a bare scenario name
// is scenarios/NAME.yaml there). Returns false with `*error` naming the file, the line, the key
// and what would do: bad keys or values, an unknown plot check or parameter, a path into the
// scenario that does not exist, a value the scenario's parser refuses.
bool LoadSweep(const std::string& path, const std::string& source_dir, SweepSpec* out,
               std::string* error);
// The same on text in memory (`path` names it and locates a relative scenario).
bool ParseSweep(const std::string& text, const std::string& path, const std::string& source_dir,
                SweepSpec* out, std::string* error);

// Sets `value` at `key` (a.b, list[2].c) in the YAML text of a scenario. Missing mapping keys
// are created; a list index must exist. False with `*why` otherwise.
bool SetKey(const std::string& yaml, const std::string& key, const Value& value,
            std::string* out_yaml, std::string* why);

// A number as text that reads back as the same double: whole numbers in full (3e6 -> "3000000"),
// others in the fewest significant digits (0.1 -> "0.1", 2.5e-4 -> "0.00025").
std::string NumberText(double v);

//---------------- running ----------------

// Where the programs are, and what the runs get.
struct RunContext {
  std::string source_dir;  // data folder, cli::DataDir() (ohrp_run runs there)
  std::string bin_dir;     // ohrp_run, sim_host, the controllers, ohrp_sweep
  bool run_plots = false;  // each run's plot.png (ohrp_run without --no-plot)
};

// Writes the sweep folder `out_dir`: sweep.json (the sweep expanded) and, per variant,
// variants/vNNN/scenario.yaml and variant.json. Removes the results of an earlier run there.
bool Prepare(const SweepSpec& spec, const std::string& out_dir, std::string* error);

// The folder of variant `id` in a sweep folder.
std::string VariantDir(const std::string& out_dir, int id);

// Runs one prepared variant: `ohrp_run scenario.yaml --out run --segment SEGMENT` in its own
// process group, killed (SIGTERM, then SIGKILL after 5 s) past `time_limit` wall seconds;
// writes status.json (exit code, wall time, killed, host, Slurm's job and task ids from the
// environment). Returns ohrp_run's exit code (124 when killed at the time limit).
int RunVariant(const std::string& variant_dir, const std::string& segment, double time_limit,
               const RunContext& ctx);

// A segment name no other run on the same machine uses: sweep_<tag>_<id>.
std::string SegmentName(const std::string& tag, int id);

//---------------- results ----------------

// What one variant gave.
struct CheckValue {
  std::string name;
  double value = 0;  // as the summary gives it: inf, -inf or NaN too (null there reads as NaN)
  bool passed = false;
};

struct VariantResult {
  int id = 0;
  std::vector<std::string> values;  // parameter values, in SweepSpec::parameters order
  // pass, fail (a check failed or a process ended badly), fell (the robot fell: sim_host's
  // outcome or event, or a failed not_fallen check), crashed (a process of the run ended by a
  // signal other than SIGINT, SIGTERM or SIGKILL), timeout (killed at the time limit), cancelled
  // (interrupted, or cancelled by Slurm), error (the run could not start), not run
  std::string status = "not run";
  std::string verdict;              // summary.json's verdict, empty without one
  int exit_code = -1;               // ohrp_run's, -1 without one
  double wall_time = 0;             // [s] ohrp_run's wall time (RunVariant's clock)
  double real_time_factor = 0;      // sim_host's (summary.json)
  double sim_time = 0;              // [s]
  std::vector<CheckValue> checks;   // in the order summary.json lists them
  std::string host;                 // where it ran
  std::string slurm_job, slurm_task;  // SLURM_ARRAY_JOB_ID, SLURM_ARRAY_TASK_ID; empty locally
  std::string detail;               // why it did not pass
  std::string log_dir;              // the variant's folder (its run/ holds the logs)
};

// Reads back every variant of a prepared sweep folder. `scheduler_states` gives, by variant id,
// what the scheduler says of a variant that left no status.json (e.g. Slurm's CANCELLED,
// TIMEOUT, FAILED); such a variant is cancelled, timeout or error with that detail.
std::vector<VariantResult> Gather(const SweepSpec& spec, const std::string& out_dir,
                                  const std::map<int, std::string>& scheduler_states = {});

// Writes sweep.csv, table.md and one plot per PlotSpec (plot_<check>_vs_<key>.png, by
// tools/sweep/plot_sweep.py) into out_dir; returns the markdown table in *markdown.
bool WriteReport(const SweepSpec& spec, const std::vector<VariantResult>& results,
                 const std::string& out_dir, const RunContext& ctx, std::string* markdown,
                 std::string* error);

//---------------- executors ----------------

struct Executor {
  enum Kind { kLocal, kSlurm } kind = kLocal;
  int cpus_per_variant = 2;          // CPUs one variant needs: a lock-stepped pair, sim_host and
                                     // its controller (local: jobs default; Slurm: --cpus-per-task)
  int jobs = 0;                      // local: variants at once; 0: the cores / cpus_per_variant
  std::string partition;             // slurm: --partition (empty: the cluster's default)
  std::string time;                  // slurm: --time per task (empty: the time limit + 1 min)
  std::vector<std::string> sbatch_args;  // slurm: more sbatch options, as given
  int max_running = 0;               // slurm: tasks at once (--array=0-N%M); 0: no limit
  double poll_interval = 2;          // slurm: [s] between squeue polls
  bool progress = true;              // progress lines on stderr
};

// What a sweep run gave.
struct SweepOutcome {
  std::vector<VariantResult> results;
  double wall_time = 0;        // [s] from the first start to the last result
  std::string slurm_job;       // the array job's id (slurm)
  bool interrupted = false;    // SIGINT/SIGTERM: the variants not run are reported cancelled
  std::string error;           // the executor could not run (sbatch refused...); results still
                               // hold every variant
};

// Prepares `out_dir`, runs every variant with the executor and gathers the results (the same
// gathering for both executors). The report is not written (WriteReport).
SweepOutcome RunSweep(const SweepSpec& spec, const Executor& executor, const std::string& out_dir,
                      const RunContext& ctx);

// The Slurm array task's side: the variant `offset` + SLURM_ARRAY_TASK_ID of the prepared sweep
// folder (an array chunk's first variant, see ChunkArray), on segment
// sweep_<SLURM_ARRAY_JOB_ID>_<variant>. Returns RunVariant's code, 2 when the environment or
// the folder is not a sweep task's.
int RunSlurmTask(const std::string& out_dir, const RunContext& ctx, int offset = 0);

//---------------- a sweep folder later: gather, resume ----------------

// Reads a prepared sweep folder back as its spec (sweep.json and each variants/vNNN/variant.json:
// name, scenario, time limit, parameters and their values, each variant's values, the plots),
// without the sweep file: what --gather and --resume need after the submitting process died.
// variant_scenarios stays empty (each variant's scenario.yaml is in its folder). False with
// `*error` naming the file when the folder is not a sweep folder.
bool LoadSweepFolder(const std::string& out_dir, SweepSpec* out, std::string* error);

// The variants of a folder still to run: no status.json (never started, or its sweep process
// died while it ran), or cancelled (interrupted). A variant that passed, failed, fell, crashed,
// timed out or could not run is finished.
std::vector<int> UnfinishedVariants(const SweepSpec& spec, const std::string& out_dir);

// Runs the variants `ids` of the prepared folder with the executor (the others are left as they
// are) and gathers every variant. `resume` says so on the progress line.
SweepOutcome RunVariants(const SweepSpec& spec, const std::vector<int>& ids,
                         const Executor& executor, const std::string& out_dir,
                         const RunContext& ctx);

// Gathers a sweep folder as it is: first waits (polling squeue) for the Slurm array jobs it
// records (slurm/jobs.json) that are still pending or running, then asks Slurm what became of
// their tasks that left no status (as RunSweep does), then Gather. Ctrl-C stops the wait (the
// jobs go on) and gathers what is there.
SweepOutcome GatherFolder(const SweepSpec& spec, const std::string& out_dir,
                          const Executor& executor);

//---------------- Slurm's array limit ----------------

// One sbatch --array job of a chunked sweep: task i runs variant offset + i.
struct ArrayChunk {
  int offset = 0;
  std::string indices;  // the --array list: "0-999", "0-3,7,9-12"
  int count = 0;        // tasks
};

// Splits variant ids (any order, no duplicates) into array jobs whose task indices stay below
// `max_array_size` (Slurm's MaxArraySize: indices 0 .. MaxArraySize - 1): chunk k holds the ids
// in [k M, (k + 1) M), offset k M; consecutive ids are written as ranges.
std::vector<ArrayChunk> ChunkArray(std::vector<int> ids, int max_array_size);

// MaxArraySize from the text of `scontrol show config` ("MaxArraySize = 1001"); 0 when absent.
int ParseMaxArraySize(const std::string& scontrol_config);

}  // namespace ohrp::sweep
