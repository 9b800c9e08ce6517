// Reading a sweep folder back: one result per variant, whatever happened to it (see sweep.h).
// Both executors call this after their runs; nothing here knows which one ran the variants.
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
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

// Typed reads that never throw, whatever the file holds (a value of the wrong type, a number
// written as null: nlohmann writes a non-finite double as null).
std::string Text(const nlohmann::json& j, const char* key, const std::string& otherwise = "") {
  const auto it = j.find(key);
  return it != j.end() && it->is_string() ? it->get<std::string>() : otherwise;
}
bool Flag(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_boolean() && it->get<bool>();
}
int Int(const nlohmann::json& j, const char* key, int otherwise) {
  const auto it = j.find(key);
  return it != j.end() && it->is_number_integer() ? it->get<int>() : otherwise;
}
// a number: a JSON number, a string "inf", "-inf", "nan" (as the runner may write them), or null
// (a non-finite double written by nlohmann: NaN here, said in *non_finite); `otherwise` when absent
double Number(const nlohmann::json& j, const char* key, double otherwise, bool* non_finite = nullptr) {
  const auto it = j.find(key);
  if (it == j.end()) return otherwise;
  double v = otherwise;
  if (it->is_number()) {
    v = it->get<double>();
  } else if (it->is_null()) {
    v = std::numeric_limits<double>::quiet_NaN();
  } else if (it->is_string()) {
    const std::string t = it->get<std::string>();
    char* end = nullptr;
    v = std::strtod(t.c_str(), &end);
    if (end == t.c_str()) v = std::numeric_limits<double>::quiet_NaN();
  }
  if (non_finite && !std::isfinite(v)) *non_finite = true;
  return v;
}
nlohmann::json Array(const nlohmann::json& j, const char* key) {
  const auto it = j.find(key);
  return it != j.end() && it->is_array() ? *it : nlohmann::json::array();
}

// the first failed check's name and detail, for the report
std::string FirstFailure(const nlohmann::json& summary) {
  for (const auto& c : Array(summary, "checks"))
    if (c.is_object() && !Flag(c, "passed")) return Text(c, "name", "?") + ": " + Text(c, "detail");
  return "";
}

// Did the robot fall? sim_host's own verdict (its summary's outcome or an event naming a fall),
// or a failed not_fallen check of the scenario. The reason, or "".
std::string FallOf(const nlohmann::json& sim, const nlohmann::json& summary) {
  auto is_fall = [](const std::string& s) {
    return s.find("fall") != std::string::npos || s.find("fell") != std::string::npos;
  };
  const std::string outcome = Text(sim, "outcome");
  if (is_fall(outcome)) {
    const std::string detail = Text(sim, "detail");
    return "sim_host: " + outcome + (detail.empty() ? "" : ": " + detail);
  }
  for (const auto& e : Array(sim, "events")) {
    if (e.is_object() && is_fall(Text(e, "event"))) {
      char t[64];
      std::snprintf(t, sizeof(t), " at t=%.3f s", Number(e, "time", 0));
      return "sim_host: " + Text(e, "event") + t;
    }
  }
  for (const auto& c : Array(summary, "checks"))
    if (c.is_object() && Text(c, "name") == "not_fallen" && !Flag(c, "passed"))
      return "not_fallen: " + Text(c, "detail");
  return "";
}

// A process of the run ended by a signal of its own making (SIGSEGV, SIGABRT, SIGBUS, SIGFPE...):
// exit code 128 + the signal. SIGINT and SIGTERM (an interruption, the end of a run) and SIGKILL
// (what the runner and the time limit send to a process that would not end) are not crashes.
// Which process and signal, or "".
std::string CrashOf(int ohrp_run_code, const nlohmann::json& summary) {
  auto crashed = [](int code) {
    return code > 128 && code < 128 + 65 && code != 128 + SIGINT && code != 128 + SIGTERM &&
           code != 128 + SIGKILL;
  };
  auto describe = [](const std::string& who, int code) {
    const char* name = strsignal(code - 128);
    return who + " ended by signal " + std::to_string(code - 128) + " (" + (name ? name : "?") + ")";
  };
  if (crashed(ohrp_run_code)) return describe("ohrp_run", ohrp_run_code);
  for (const auto& p : Array(summary, "processes"))
    if (p.is_object() && crashed(Int(p, "exit_code", 0)))
      return describe(Text(p, "name", "a process"), Int(p, "exit_code", 0));
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
    if (!ReadJson(r.log_dir + "/status.json", &status) || !status.is_object()) {
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
      r.detail = state.empty() ? "no status.json: the variant did not run, or the sweep's process "
                                 "died while it ran (--resume runs it)"
                               : state;
      results.push_back(r);
      continue;
    }
    r.exit_code = Int(status, "exit_code", -1);
    r.wall_time = Number(status, "wall_time", 0.0);
    r.host = Text(status, "host");
    r.slurm_job = Text(status, "slurm_array_job_id");
    r.slurm_task = Text(status, "slurm_array_task_id");

    // what ohrp_run found (its summary.json), when it got that far, and sim_host's own summary
    nlohmann::json summary, sim;
    const bool have_summary = ReadJson(r.log_dir + "/run/summary.json", &summary) && summary.is_object();
    if (!ReadJson(r.log_dir + "/run/sim_summary.json", &sim) || !sim.is_object()) sim = nlohmann::json::object();
    std::vector<std::string> non_finite;  // the values that are not numbers, said in the detail
    if (have_summary) {
      r.verdict = Text(summary, "verdict");
      bool bad = false;
      r.real_time_factor = Number(summary, "real_time_factor", 0.0, &bad);
      if (bad) non_finite.push_back("real_time_factor");
      bad = false;
      r.sim_time = Number(summary, "sim_time", 0.0, &bad);
      if (bad) non_finite.push_back("sim_time");
      for (const auto& c : Array(summary, "checks")) {
        if (!c.is_object()) continue;
        CheckValue cv;
        cv.name = Text(c, "name", "?");
        bool nf = false;
        cv.value = Number(c, "value", 0.0, &nf);
        cv.passed = Flag(c, "passed");
        // a second check of the same name gets #2, #3...
        int same = 1;
        for (const auto& other : r.checks)
          if (other.name == cv.name || other.name.rfind(cv.name + "#", 0) == 0) ++same;
        if (same > 1) cv.name += "#" + std::to_string(same);
        if (nf) non_finite.push_back(cv.name + " = " + NumberText(cv.value));
        r.checks.push_back(cv);
      }
    }
    const std::string fall = FallOf(sim, summary), crash = CrashOf(r.exit_code, summary);
    if (Flag(status, "killed_at_time_limit")) {
      r.status = "timeout";
      r.detail = "killed at the time limit of " + NumberText(Number(status, "time_limit", 0.0)) +
                 " s wall (see " + r.log_dir + "/ohrp_run.out)";
    } else if (Flag(status, "cancelled") || r.exit_code == 130 || r.verdict == "interrupted") {
      r.status = "cancelled";
      r.detail = "interrupted (see " + r.log_dir + "/ohrp_run.out)";
    } else if (!crash.empty()) {
      r.status = "crashed";
      r.detail = crash + " (see " + r.log_dir + ")";
    } else if (!fall.empty()) {
      r.status = "fell";
      r.detail = fall;
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
    if (!non_finite.empty()) {
      std::string list;
      for (const auto& n : non_finite) list += (list.empty() ? "" : ", ") + n;
      r.detail += (r.detail.empty() ? "" : "; ") + std::string("not finite: ") + list;
    }
    results.push_back(r);
  }
  return results;
}

}  // namespace ohrp::sweep
