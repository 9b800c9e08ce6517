// The executor's command-line options (see sweep/executor_options.h).
#include "sweep/executor_options.h"

#include "cli/command_line.h"

namespace ohrp::sweep {

void AddExecutorOptions(CLI::App* app, Executor* ex, const std::string& what) {
  app->add_option("--jobs,-j", ex->jobs, "local: " + what + " at once (default: the number of "
                                         "cores / --cpus-per-variant)")
      ->check(ohrp::cli::InRange(0, 256));
  app->add_option("--cpus-per-variant", ex->cpus_per_variant,
                  "CPUs one of the " + what + " needs: a lock-stepped pair (sim_host and its "
                  "controller) needs 2; sets the default --jobs, and --slurm's --cpus-per-task "
                  "(unless --sbatch-arg gives one)")
      ->capture_default_str()->check(ohrp::cli::InRange(1, 256));
  app->add_flag_callback(
      "--slurm", [ex] { ex->kind = Executor::kSlurm; },
      "run the " + what + " as a Slurm array job (sbatch --array; several when there are more "
      "than the site's MaxArraySize) and gather the results when it ends");
  app->add_option("--partition", ex->partition, "--slurm: the partition (default: the cluster's)");
  app->add_option("--time", ex->time, "--slurm: each task's time limit as sbatch takes it "
                                      "(default: the sweep's time_limit + 1 min)");
  app->add_option("--max-running", ex->max_running, "--slurm: tasks at once (--array=0-N%M; 0: no limit)")
      ->check(ohrp::cli::InRange(0, 100000));
  app->add_option("--sbatch-arg", ex->sbatch_args, "--slurm: one more sbatch option, e.g. "
                                                   "--sbatch-arg=--account=robots (repeatable)");
  app->add_option("--poll", ex->poll_interval, "--slurm: seconds between squeue polls")
      ->check(ohrp::cli::InRange(0.05, 600))->capture_default_str();
}

}  // namespace ohrp::sweep
