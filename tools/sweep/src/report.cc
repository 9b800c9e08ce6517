// The sweep's report: sweep.csv, table.md and the plots (see sweep.h, docs/sweep.md).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "sweep/sweep.h"
#include "tool_process/run_command.h"

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

// a CSV field, quoted when it must be
std::string Field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string Num(double v) { return NumberText(v); }

// a markdown cell (no '|' or line break inside)
std::string Cell(std::string s) {
  for (char& c : s)
    if (c == '|' || c == '\n') c = c == '|' ? '/' : ' ';
  return s;
}

std::string Short(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}

// every check name, in the order of first appearance
std::vector<std::string> CheckNames(const std::vector<VariantResult>& results) {
  std::vector<std::string> names;
  std::set<std::string> seen;
  for (const auto& r : results)
    for (const auto& c : r.checks)
      if (seen.insert(c.name).second) names.push_back(c.name);
  return names;
}

const CheckValue* Find(const VariantResult& r, const std::string& name) {
  for (const auto& c : r.checks)
    if (c.name == name) return &c;
  return nullptr;
}

// a file name part: letters, digits, '_', '-', '.'
std::string Slug(const std::string& s) {
  std::string out;
  for (char c : s) out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return out;
}

}  // namespace

bool WriteReport(const SweepSpec& spec, const std::vector<VariantResult>& results,
                 const std::string& out_dir, const RunContext& ctx, std::string* markdown,
                 std::string* error) {
  const auto checks = CheckNames(results);

  //---------------- sweep.csv ----------------
  const std::string csv_path = (fs::path(out_dir) / "sweep.csv").string();
  {
    std::ofstream csv(csv_path);
    csv << "variant";
    for (const auto& p : spec.parameters) csv << "," << Field(p.key);
    csv << ",status,verdict,exit_code,real_time_factor,wall_time,sim_time,host,slurm_job,slurm_task";
    for (const auto& c : checks) csv << "," << Field(c) << "," << Field(c + "_passed");
    csv << ",log_dir,detail\n";
    for (const auto& r : results) {
      csv << r.id;
      for (const auto& v : r.values) csv << "," << Field(v);
      csv << "," << r.status << "," << r.verdict << "," << r.exit_code << "," << Num(r.real_time_factor)
          << "," << Num(r.wall_time) << "," << Num(r.sim_time) << "," << Field(r.host) << ","
          << r.slurm_job << "," << r.slurm_task;
      for (const auto& name : checks) {
        const CheckValue* c = Find(r, name);
        csv << "," << (c ? Num(c->value) : "") << "," << (c ? (c->passed ? "true" : "false") : "");
      }
      csv << "," << Field(r.log_dir) << "," << Field(r.detail) << "\n";
    }
    if (!csv) {
      *error = "cannot write " + csv_path;
      return false;
    }
  }

  //---------------- table.md ----------------
  // cells appended one by one (GCC 12 warns falsely on "x" + std::string chains)
  std::string md = "| variant |", rule = "|---:|";
  auto cell = [&md](const std::string& text) {
    md += ' ';
    md += Cell(text);
    md += " |";
  };
  for (const auto& p : spec.parameters) {
    cell(p.key);
    rule += "---:|";
  }
  cell("status");
  rule += "---|";
  for (const auto& c : checks) {
    cell(c);
    rule += "---:|";
  }
  cell("real time");
  cell("wall [s]");
  cell("logs / why");
  md += '\n';
  md += rule;
  md += "---:|---:|---|\n";
  std::map<std::string, int> counts;
  for (const auto& r : results) {
    ++counts[r.status];
    md += '|';
    cell(std::to_string(r.id));
    for (const auto& v : r.values) cell(v);
    cell(r.status);
    for (const auto& name : checks) {
      const CheckValue* c = Find(r, name);
      cell(!c ? std::string("-") : c->passed ? Short(c->value) : Short(c->value) + " FAIL");
    }
    cell(r.real_time_factor > 0 ? Short(r.real_time_factor) + "x" : std::string("-"));
    cell(r.exit_code >= 0 || r.wall_time > 0 ? Short(r.wall_time) : std::string("-"));
    cell(r.status == "pass" ? std::string() : r.detail);
    md += '\n';
  }
  md += '\n';
  md += std::to_string(results.size());
  md += " variants:";
  for (const auto& [status, n] : counts) {
    md += ' ';
    md += std::to_string(n);
    md += ' ';
    md += status;
    md += ',';
  }
  md.back() = '\n';
  const std::string md_path = (fs::path(out_dir) / "table.md").string();
  std::ofstream(md_path) << "# sweep " << spec.name << " (" << spec.scenario_file << ")\n\n" << md;
  *markdown = md;

  //---------------- plots ----------------
  if (spec.plots.empty()) return true;
  const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
  // an argument vector: no name from the sweep file reaches a shell
  std::vector<std::string> argv = {python, ctx.source_dir + "/tools/sweep/plot_sweep.py", csv_path};
  for (const auto& p : spec.plots) {
    bool log_scale = false;
    for (const auto& param : spec.parameters) log_scale = log_scale || (param.key == p.against && param.log_scale);
    const std::string file = (fs::path(out_dir) / ("plot_" + Slug(p.check) + "_vs_" + Slug(p.against) + ".png")).string();
    argv.insert(argv.end(), {"--plot", p.check, p.against, file, log_scale ? "log" : "linear"});
  }
  // the zip groups (parameters whose value index is the same in every variant): a plot against one
  // of them draws one line per combination of the parameters outside its group
  const size_t np = spec.parameters.size();
  std::vector<bool> grouped(np, false);
  for (size_t a = 0; a < np; ++a) {
    if (grouped[a]) continue;
    std::string group = spec.parameters[a].key;
    for (size_t b = a + 1; b < np; ++b) {
      bool same = spec.parameters[a].values.size() == spec.parameters[b].values.size();
      for (size_t v = 0; v < spec.variants.size() && same; ++v)
        same = spec.variants[v].value_index[a] == spec.variants[v].value_index[b];
      if (same && spec.variants.size() > 1) grouped[b] = true, group += "|" + spec.parameters[b].key;
    }
    if (group != spec.parameters[a].key) argv.insert(argv.end(), {"--zip", group});
  }
  // an argument vector, no shell (tool_process/run_command.h); the file is the last attempt's
  const std::string plot_stderr = out_dir + "/plot.stderr";
  fs::remove(plot_stderr);
  std::string why;
  if (ohrp::tool::RunCommand(argv, plot_stderr, &why) != 0) {
    *error = "the plots could not be made (" + (why.empty() ? "see " + plot_stderr : why) + ")";
    return false;
  }
  return true;
}

}  // namespace ohrp::sweep
