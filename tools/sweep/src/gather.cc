// Reading a sweep folder back: one result per variant, whatever happened to it (see sweep.h).
// Both executors call this after their runs; nothing here knows which one ran the variants.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "sweep/sweep.h"

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

bool ReadJson(const std::string& path, nlohmann::json* out) {
  std::ifstream in(path);
  if (!in) return false;
  try {
    in >> *out;
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// the first failed check's name and detail, for the report
std::string FirstFailure(const nlohmann::json& summary) {
  for (const auto& c : summary.value("checks", nlohmann::json::array()))
    if (!c.value("passed", false))
      return c.value("name", std::string("?")) + ": " + c.value("detail", std::string());
  return "";
}

}  // namespace

std::vector<VariantResult> Gather(const SweepSpec& spec, const std::string& out_dir,
                                  const std::map<int, std::string>& scheduler_states) {
  std::vector<VariantResult> results;
  for (const auto& v : spec.variants) {
    VariantResult r;
    r.id = v.id;
    for (size_t p = 0; p < spec.parameters.size(); ++p)
      r.values.push_back(spec.parameters[p].values[v.value_index[p]].text);
    r.log_dir = VariantDir(out_dir, v.id);

    // how the variant's run ended (RunVariant's status.json)
    nlohmann::json status;
    if (!ReadJson(r.log_dir + "/status.json", &status)) {
      // never ran to the end of RunVariant: what the scheduler says ("CANCELLED ...", "TIMEOUT
    // ...", Slurm's words first), else not run
      auto it = scheduler_states.find(v.id);
      const std::string state = it == scheduler_states.end() ? "" : it->second;
      auto starts = [&](const char* word) { return state.rfind(word, 0) == 0; };
      if (starts("CANCELLED") || starts("PENDING") || starts("PREEMPTED"))
        r.status = "cancelled";
      else if (starts("TIMEOUT") || starts("DEADLINE"))
        r.status = "timeout";
      else if (!state.empty())
        r.status = "error";
      r.detail = state.empty() ? "no status.json: the variant did not run" : state;
      results.push_back(r);
      continue;
    }
    r.exit_code = status.value("exit_code", -1);
    r.wall_time = status.value("wall_time", 0.0);
    r.host = status.value("host", std::string());
    r.slurm_job = status.value("slurm_array_job_id", std::string());
    r.slurm_task = status.value("slurm_array_task_id", std::string());

    // what ohrp_run found (its summary.json), when it got that far
    nlohmann::json summary;
    const bool have_summary = ReadJson(r.log_dir + "/run/summary.json", &summary);
    if (have_summary) {
      r.verdict = summary.value("verdict", std::string());
      r.real_time_factor = summary.value("real_time_factor", 0.0);
      r.sim_time = summary.value("sim_time", 0.0);
      for (const auto& c : summary.value("checks", nlohmann::json::array())) {
        CheckValue cv;
        cv.name = c.value("name", std::string("?"));
        cv.value = c.value("value", 0.0);
        cv.passed = c.value("passed", false);
        // a second check of the same name gets #2, #3...
        int same = 1;
        for (const auto& other : r.checks)
          if (other.name == cv.name || other.name.rfind(cv.name + "#", 0) == 0) ++same;
        if (same > 1) cv.name += "#" + std::to_string(same);
        r.checks.push_back(cv);
      }
    }
    if (status.value("killed_at_time_limit", false)) {
      r.status = "timeout";
      r.detail = "killed at the time limit of " + NumberText(status.value("time_limit", 0.0)) +
                 " s wall (see " + r.log_dir + "/ohrp_run.out)";
    } else if (status.value("cancelled", false) || r.exit_code == 130 || r.verdict == "interrupted") {
      r.status = "cancelled";
      r.detail = "interrupted (see " + r.log_dir + "/ohrp_run.out)";
    } else if (r.exit_code == 0 && r.verdict == "pass") {
      r.status = "pass";
    } else if (r.exit_code == 1 && have_summary) {
      r.status = "fail";
      r.detail = FirstFailure(summary);
    } else {
      r.status = "error";
      r.detail = "ohrp_run exited with " + std::to_string(r.exit_code) +
                 (have_summary ? "" : " without a summary") + " (see " + r.log_dir + "/ohrp_run.out)";
    }
    results.push_back(r);
  }
  return results;
}

}  // namespace ohrp::sweep
