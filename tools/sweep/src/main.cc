// ohrp_sweep: many headless runs of a scenario with parameters varied, locally or as a Slurm
// array job, gathered into one report (see sweep/sweep.h and docs/sweep.md).
#include <ctime>
#include <filesystem>

#include "cli/command_line.h"
#include "cli/data_dir.h"
#include "sweep/executor_options.h"
#include "sweep/sweep.h"

namespace fs = std::filesystem;

namespace {

// the report of a sweep run, resumed or gathered: sweep.csv, table.md (printed), the plots; the
// exit code
int Report(const ohrp::sweep::SweepSpec& spec, const ohrp::sweep::SweepOutcome& outcome,
           const std::string& out_dir, const ohrp::sweep::RunContext& ctx) {
  std::string markdown, error;
  if (!outcome.error.empty()) std::fprintf(stderr, "ohrp_sweep: %s\n", outcome.error.c_str());
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

}  // namespace

int main(int argc, char** argv) {
  std::string file, out_dir, task_dir, gather_dir, resume_dir;
  int task_offset = 0;
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
  app.add_option("--task-offset", task_offset, "with --task: the array chunk's first variant (what "
                                               "--slurm submits when the sweep is larger than the "
                                               "site's MaxArraySize)")
      ->check(ohrp::cli::InRange(0, 100000000));
  app.add_option("--gather", gather_dir,
                 "report an existing sweep folder as it is, without its sweep file (e.g. after the "
                 "submitting process died): waits for its Slurm jobs still queued or running, then "
                 "writes sweep.csv, table.md and the plots; runs nothing")
      ->check(CLI::ExistingDirectory);
  app.add_option("--resume", resume_dir,
                 "run the variants of an existing sweep folder that have not finished (never "
                 "started, cancelled, or running when its sweep process died), with the executor "
                 "options given, then report the whole folder; finished variants are not run again")
      ->check(CLI::ExistingDirectory);
  app.footer(
      "Exit codes: 0 every variant passed, 1 a variant failed, fell, crashed, timed out, was cancelled or could\n"
      "not run (the report says which, with its logs), or the report or the job could not be made,\n"
      "2 bad option or sweep file, 130 interrupted.");
  if (const int code = ohrp::cli::ParseCommandLine(&app, argc, argv); code >= 0) return code;
  ctx.source_dir = ohrp::cli::DataDir();
  ctx.bin_dir = fs::canonical("/proc/self/exe").parent_path().string();
  ex.progress = !quiet;

  // a Slurm array task
  if (!task_dir.empty()) return ohrp::sweep::RunSlurmTask(task_dir, ctx, task_offset);

  ohrp::sweep::SweepSpec spec;
  std::string error;
  ohrp::sweep::SweepOutcome outcome;
  if (!gather_dir.empty() || !resume_dir.empty()) {
    // a sweep folder later: its spec from the folder itself
    if (!gather_dir.empty() && !resume_dir.empty()) {
      std::fprintf(stderr, "ohrp_sweep: --gather and --resume exclude each other\n");
      return 2;
    }
    if (!file.empty() || !out_dir.empty()) {
      std::fprintf(stderr, "ohrp_sweep: --gather/--resume take the sweep folder only (no sweep file, no --out)\n");
      return 2;
    }
    out_dir = fs::absolute(gather_dir.empty() ? resume_dir : gather_dir).lexically_normal().string();
    if (!ohrp::sweep::LoadSweepFolder(out_dir, &spec, &error)) {
      std::fprintf(stderr, "ohrp_sweep: %s\n", error.c_str());
      return 2;
    }
    if (!gather_dir.empty()) {
      outcome = ohrp::sweep::GatherFolder(spec, out_dir, ex);
    } else {
      const std::vector<int> ids = ohrp::sweep::UnfinishedVariants(spec, out_dir);
      std::fprintf(stderr, "ohrp_sweep: resuming %s: %zu of %zu variants to run\n", out_dir.c_str(),
                   ids.size(), spec.variants.size());
      outcome = ohrp::sweep::RunVariants(spec, ids, ex, out_dir, ctx);
    }
    return Report(spec, outcome, out_dir, ctx);
  }

  if (file.empty()) {
    std::fprintf(stderr, "ohrp_sweep: a sweep file is required (or --task DIR inside a Slurm array job)\n");
    return 2;
  }
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

  return Report(spec, ohrp::sweep::RunSweep(spec, ex, out_dir, ctx), out_dir, ctx);
}
