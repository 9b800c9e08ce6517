// The refinement's simulations as sweeps (see simulate.h).
#include "simulate.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "sweep/sweep.h"

namespace ohrp::identify {

bool SimulateStage(const IdentifyOptions& o, const std::string& stage,
                   const std::vector<std::pair<double, double>>& kd,
                   std::vector<std::string>* variant_dirs, nlohmann::json* record, std::string* error) {
  namespace fs = std::filesystem;
  // the sweep as a sweep file (kept next to its folder: `ohrp sweep` runs it again as it is)
  std::string ks, ds;
  for (const auto& [k, d] : kd) {
    ks += (ks.empty() ? "" : ", ") + sweep::NumberText(k);
    ds += (ds.empty() ? "" : ", ") + sweep::NumberText(d);
  }
  const std::string scenario = fs::absolute(o.scenario).lexically_normal().string();
  std::string quoted = "'";
  for (char c : scenario) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  quoted += "'";
  const std::string text = "# ohrp identify, stage " + stage + ": the experiment at each (K, D)\n"
                           "name: identify_" + stage + "\n"
                           "scenario: " + quoted + "\n"
                           "parameters:\n"
                           "  - zip:\n"
                           "      - {key: contact_params.stiffness, values: [" + ks + "]}\n"
                           "      - {key: contact_params.damping, values: [" + ds + "]}\n";
  const std::string dir = o.out_dir + "/" + stage;
  const std::string file = o.out_dir + "/" + stage + ".yaml";
  std::ofstream(file) << text;
  sweep::SweepSpec spec;
  if (!sweep::ParseSweep(text, file, o.source_dir, &spec, error)) return false;
  const sweep::RunContext ctx{o.source_dir, o.bin_dir, false};
  const sweep::SweepOutcome out = sweep::RunSweep(spec, o.executor, dir, ctx);
  std::string markdown, report_error;
  if (!out.results.empty() && !sweep::WriteReport(spec, out.results, dir, ctx, &markdown, &report_error))
    std::fprintf(stderr, "ohrp identify: stage %s: %s\n", stage.c_str(), report_error.c_str());
  *record = {{"stage", stage}, {"dir", dir}, {"variants", kd.size()}, {"wall_time", out.wall_time},
             {"executor", o.executor.kind == sweep::Executor::kSlurm ? "slurm" : "local"}};
  if (!out.slurm_job.empty()) (*record)["slurm_job"] = out.slurm_job;
  if (out.interrupted) {
    *error = "interrupted during the simulations of stage " + stage + " (" + dir + ")";
    return false;
  }
  if (!out.error.empty()) {
    *error = "stage " + stage + " (" + dir + "): " + out.error;
    return false;
  }
  if (out.results.size() != kd.size()) {
    *error = "stage " + stage + " (" + dir + "): " + std::to_string(out.results.size()) +
             " results for " + std::to_string(kd.size()) + " simulations";
    return false;
  }
  variant_dirs->clear();
  for (size_t i = 0; i < kd.size(); ++i) {
    const sweep::VariantResult& r = out.results[i];
    if (r.id != static_cast<int>(i)) {
      *error = "stage " + stage + " (" + dir + "): the results are not in the variants' order";
      return false;
    }
    // a run whose checks failed still simulated the experiment (its log is measured); one that
    // timed out, was cancelled or could not run did not
    const bool ran = r.status == "pass" || r.status == "fail";
    if (!ran || !fs::exists(r.log_dir + "/run/log.csv")) {
      char kdt[96];
      std::snprintf(kdt, sizeof(kdt), "K = %.6g N/m, D = %.6g s/m", kd[i].first, kd[i].second);
      *error = "the simulation with " + std::string(kdt) + " (stage " + stage + ", " + r.log_dir +
               ") ended '" + r.status + "'" + (r.detail.empty() ? "" : ": " + r.detail) +
               (fs::exists(r.log_dir + "/run/log.csv") ? "" : "; it wrote no log");
      return false;
    }
    variant_dirs->push_back(r.log_dir);
  }
  return true;
}

}  // namespace ohrp::identify
