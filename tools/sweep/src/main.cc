// ohrp_sweep: many headless runs of a scenario with parameters varied, locally or as a Slurm
// array job, gathered into one report (see sweep/sweep.h and docs/sweep.md).
#include <ctime>
#include <filesystem>

#include "cli/command_line.h"
#include "sweep/executor_options.h"
#include "sweep/sweep.h"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  std::string file, out_dir, task_dir;
  ohrp::sweep::Executor ex;
  ohrp::sweep::RunContext ctx;
  bool check_only = false, quiet = false;
  CLI::App app{
      "ohrp_sweep: one scenario run many times with parameters varied (scenario keys by path:\n"
      "lists, ranges, grids, zipped lists), each variant one headless ohrp_run with its own folder\n"
      "and segment under a wall-time limit; locally (parallel, --jobs) or as a Slurm array job\n"
      "(--slurm). Writes sweep.csv, table.md (also printed) and the sweep file's plots into --out.\n"
      "Format: docs/sweep.md."};
  app.add_option("sweep", file, "sweep file (YAML)")->check(CLI::ExistingFile);
  app.add_option("--out", out_dir, "sweep folder (default: runs/sweep-<name>-<date>-<time>)");
  ohrp::sweep::AddExecutorOptions(&app, &ex);
  app.add_flag("--run-plots", ctx.run_plots, "each variant's own plot.png (ohrp_run without --no-plot)");
  app.add_flag("--check", check_only, "read and check the sweep file, list the variants, run nothing");
  app.add_flag("--quiet,-q", quiet, "no progress lines");
  app.add_option("--task", task_dir, "inside a Slurm array task: run variant SLURM_ARRAY_TASK_ID of "
                                     "this prepared sweep folder (what --slurm submits)");
  app.footer(
      "Exit codes: 0 every variant passed, 1 a variant failed, timed out, was cancelled or could\n"
      "not run (the report says which, with its logs), or the report or the job could not be made,\n"
      "2 bad option or sweep file, 130 interrupted.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ctx.source_dir = OHRP_SOURCE_DIR;
  ctx.bin_dir = fs::canonical("/proc/self/exe").parent_path().string();
  ex.progress = !quiet;

  // a Slurm array task
  if (!task_dir.empty()) return ohrp::sweep::RunSlurmTask(task_dir, ctx);

  if (file.empty()) {
    std::fprintf(stderr, "ohrp_sweep: a sweep file is required (or --task DIR inside a Slurm array job)\n");
    return 2;
  }
  ohrp::sweep::SweepSpec spec;
  std::string error;
  if (!ohrp::sweep::LoadSweep(file, ctx.source_dir, &spec, &error)) {
    std::fprintf(stderr, "ohrp_sweep: %s\n", error.c_str());
    return 2;
  }
  if (check_only) {
    std::printf("sweep %s: %zu variants of %s, time limit %g s each\n", spec.name.c_str(),
                spec.variants.size(), spec.scenario_file.c_str(), spec.time_limit);
    for (const auto& v : spec.variants) {
      std::printf("  v%03d", v.id);
      for (size_t p = 0; p < spec.parameters.size(); ++p)
        std::printf(" %s=%s", spec.parameters[p].key.c_str(), spec.parameters[p].values[v.value_index[p]].text.c_str());
      std::printf("\n");
    }
    return 0;
  }
  if (out_dir.empty()) {
    char b[32];
    const std::time_t t = std::time(nullptr);
    std::strftime(b, sizeof(b), "%Y%m%d-%H%M%S", std::localtime(&t));
    out_dir = "runs/sweep-" + spec.name + "-" + b;
  }
  out_dir = fs::absolute(out_dir).lexically_normal().string();

  const auto outcome = ohrp::sweep::RunSweep(spec, ex, out_dir, ctx);
  if (!outcome.error.empty()) std::fprintf(stderr, "ohrp_sweep: %s\n", outcome.error.c_str());
  std::string markdown;
  const bool reported = !outcome.results.empty() &&
                        ohrp::sweep::WriteReport(spec, outcome.results, out_dir, ctx, &markdown, &error);
  if (!reported && !outcome.results.empty()) std::fprintf(stderr, "ohrp_sweep: %s\n", error.c_str());
  std::printf("%s", markdown.c_str());
  std::fprintf(stderr, "ohrp_sweep: %zu variants in %.1f s wall%s%s; sweep.csv, table.md%s in %s\n",
               outcome.results.size(), outcome.wall_time,
               outcome.slurm_job.empty() ? "" : " (Slurm job ", outcome.slurm_job.empty() ? "" : (outcome.slurm_job + ")").c_str(),
               spec.plots.empty() ? "" : " and plots", out_dir.c_str());
  if (outcome.interrupted) return 130;
  if (!outcome.error.empty() || !reported) return 1;
  for (const auto& r : outcome.results)
    if (r.status != "pass") return 1;
  return 0;
}
