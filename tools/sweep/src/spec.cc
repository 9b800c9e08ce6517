// Sweep files (see sweep.h and docs/sweep.md): every key and value is checked here, and every
// variant's scenario through the runner's own parser, before anything runs.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "runner/scenario.h"
#include "keys.h"
#include "spec_parameters.h"
#include "sweep/sweep.h"
#include "yaml_read.h"  // the runner's typed reads (ReadNumber, ReadText, ...)

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

using runner::JoinNames;
using runner::KnownKeysOnly;
using runner::ReadNumber;
using runner::ReadText;

const std::set<std::string> kTopKeys = {"name", "scenario", "time_limit", "set", "parameters",
                                        "plots"};
const std::set<std::string> kPlotKeys = {"check", "against"};
// figures of every run that a plot may use besides the checks
const std::set<std::string> kRunFigures = {"real_time_factor", "wall_time", "sim_time"};

constexpr size_t kMaxVariants = 100000;
constexpr double kMaxTimeLimit = 1e6;  // [s]
constexpr const char* kSweep = "sweep";  // the messages' kind (the runner's reads)

// the YAML of the scenario with the `set` keys and the variant's values
bool VariantText(const SweepSpec& s, const Variant& v, std::string* out, std::string* why) {
  std::string text = s.scenario_text;
  for (const auto& [key, value] : s.set)
    if (!SetKey(text, key, value, &text, why)) return false;
  for (size_t p = 0; p < s.parameters.size(); ++p)
    if (!SetKey(text, s.parameters[p].key, s.parameters[p].values[v.value_index[p]], &text, why))
      return false;
  *out = text;
  return true;
}

std::string Describe(const SweepSpec& s, const Variant& v) {
  std::string d;
  for (size_t p = 0; p < s.parameters.size(); ++p)
    d += (p ? ", " : "") + s.parameters[p].key + "=" + s.parameters[p].values[v.value_index[p]].text;
  return d;
}

// every variant's scenario, through the runner's parser; largest duration into *duration
bool CheckVariants(SweepSpec* s, const YAML::Node& root, double* duration, std::string* error) {
  *duration = 0;
  for (const auto& v : s->variants) {
    std::string text, why;
    runner::Scenario scenario;
    char label[64];
    std::snprintf(label, sizeof(label), "v%03d", v.id);
    const std::string name = s->scenario_file + " as variant " + label;
    if (VariantText(*s, v, &text, &why) && runner::ParseScenario(text, name, &scenario, &why)) {
      *duration = std::max(*duration, scenario.duration);
      s->variant_scenarios.push_back(text);
      continue;
    }
    // blame the first parameter that alone makes the scenario refuse (else the `set` keys or
    // the parameters together)
    std::string where = AtKey(s->file, root, "parameters") + "parameters";
    for (size_t p = 0; p < s->parameters.size(); ++p) {
      std::string one = s->scenario_text, ignored;
      runner::Scenario unused;
      bool ok = true;
      for (const auto& [key, value] : s->set) ok = ok && SetKey(one, key, value, &one, &ignored);
      const Value& value = s->parameters[p].values[v.value_index[p]];
      if (ok && (!SetKey(one, s->parameters[p].key, value, &one, &ignored) ||
                 !runner::ParseScenario(one, name, &unused, &ignored))) {
        where = "sweep '" + s->file + "': line " + std::to_string(s->parameters[p].line) + ": " +
                s->parameters[p].key + " = " + value.text;
        break;
      }
    }
    *error = where + ": variant " + label + " (" + Describe(*s, v) + ") is refused: " + why;
    return false;
  }
  return true;
}

// the scenario named by `scenario:`: a bare name is scenarios/NAME.yaml in the repository, a
// path is relative to the sweep file's folder
std::string ScenarioPath(const std::string& name, const std::string& sweep_path,
                         const std::string& source_dir) {
  if (name.find('/') == std::string::npos && name.find(".yaml") == std::string::npos)
    return (fs::path(source_dir) / "scenarios" / (name + ".yaml")).string();
  if (!name.empty() && name[0] == '/') return name;
  return (fs::path(sweep_path).parent_path() / name).lexically_normal().string();
}

// name: the file's name unless given, plain enough to name a folder and a Slurm job
bool ReadName(const YAML::Node& root, const std::string& path, SweepSpec* s, std::string* error) {
  std::string why;
  s->name = fs::path(path).filename().string();
  if (s->name.size() > 5 && s->name.substr(s->name.size() - 5) == ".yaml") s->name.resize(s->name.size() - 5);
  if (root["name"] && !ReadText(root["name"], &s->name, &why)) s->name.clear();
  const bool plain = !s->name.empty() && s->name.size() <= 100 &&
                     s->name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                               "0123456789_-.") == std::string::npos;
  if (!plain) {
    *error = (root["name"] ? AtKey(path, root, "name") : "sweep '" + path + "': ") + "name: '" + s->name +
             "' must be 1 to 100 letters, digits, '_', '-' or '.' (it names the output folder and the Slurm job)" +
             (root["name"] ? "" : "; give 'name:' since the file's name is not one");
    return false;
  }
  return true;
}

// scenario: the file named, and its text
bool ReadScenarioFile(const YAML::Node& root, const std::string& path, const std::string& source_dir,
                      SweepSpec* s, std::string* error) {
  std::string scenario, why;
  if (!root["scenario"] || !ReadText(root["scenario"], &scenario, &why) || scenario.empty()) {
    *error = (root["scenario"] ? AtKey(path, root, "scenario") : "sweep '" + path + "': ") +
             "'scenario' is required: a name in scenarios/ (e.g. stand) or a path to a scenario file";
    return false;
  }
  s->scenario_file = ScenarioPath(scenario, path, source_dir);
  std::ifstream in(s->scenario_file);
  if (!in) {
    *error = AtKey(path, root, "scenario") + "scenario: '" + s->scenario_file +
             "' does not exist (a bare name is scenarios/NAME.yaml; a path is relative to the sweep file)";
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  s->scenario_text = ss.str();
  return true;
}

bool ReadTimeLimit(const YAML::Node& root, const std::string& path, SweepSpec* s, std::string* error) {
  std::string why;
  if (root["time_limit"]) {
    if (!ReadNumber(root["time_limit"], &s->time_limit, &why) || !(s->time_limit > 0) ||
        s->time_limit > kMaxTimeLimit) {
      *error = AtKey(path, root, "time_limit") + "time_limit: must be wall seconds per variant in (0, 1e6]" +
               (why.empty() ? "" : ", " + why);
      return false;
    }
  }
  return true;
}

// set: keys given to every variant, each one set on the scenario with those before it
bool ReadSet(const YAML::Node& root, const std::string& path, SweepSpec* s, std::string* error) {
  if (!root["set"]) return true;
  std::string why;
  const YAML::Node set = root["set"];
  if (!set.IsMap()) {
    *error = AtKey(path, root, "set") + "set: must be a mapping of scenario keys to values, e.g. {duration: 2.0}";
    return false;
  }
  for (const auto& kv : set) {
    std::vector<Token> tokens;
    Value v;
    std::string key = kv.first.Scalar();
    if (!SplitKey(key, &tokens, &why) || !ReadValue(kv.second, &v, &why)) {
      *error = At(path, kv.first) + "set: " + key + ": " + why;
      return false;
    }
    std::string text = s->scenario_text;
    for (const auto& [k, value] : s->set) SetKey(text, k, value, &text, &why);
    if (!SetKey(text, key, v, &text, &why)) {
      *error = At(path, kv.first) + "set: " + key + ": " + why;
      return false;
    }
    s->set.push_back({key, v});
  }
  return true;
}

// the grid: the first axis varies slowest
bool BuildGrid(const YAML::Node& root, const std::string& path,
               const std::vector<std::vector<size_t>>& axes, SweepSpec* s, std::string* error) {
  size_t total = 1;
  for (const auto& axis : axes) {
    total *= s->parameters[axis[0]].values.size();
    if (total > kMaxVariants) {
      *error = AtKey(path, root, "parameters") + "parameters: more than " + std::to_string(kMaxVariants) + " variants";
      return false;
    }
  }
  for (size_t n = 0; n < total; ++n) {
    Variant v;
    v.id = static_cast<int>(n);
    v.value_index.assign(s->parameters.size(), 0);
    size_t rest = n;
    for (size_t a = axes.size(); a-- > 0;) {
      const size_t count = s->parameters[axes[a][0]].values.size();
      for (size_t k : axes[a]) v.value_index[k] = static_cast<int>(rest % count);
      rest /= count;
    }
    s->variants.push_back(v);
  }
  return true;
}

// plots: a check of the scenario (`figures`, or a run's figure) against a parameter (`keys`)
bool ReadPlots(const YAML::Node& root, const std::string& path, const std::set<std::string>& figures,
               const std::set<std::string>& keys, SweepSpec* s, std::string* error) {
  if (!root["plots"]) return true;
  std::string why;
  const YAML::Node plots = root["plots"];
  if (!plots.IsSequence()) {
    *error = AtKey(path, root, "plots") + "plots: must be a list, e.g. - {check: base_height, against: contact_params.stiffness}";
    return false;
  }
  for (size_t i = 0; i < plots.size(); ++i) {
    const std::string where = "plots[" + std::to_string(i) + "]: ";
    if (!plots[i].IsMap()) {
      *error = At(path, plots[i]) + where + "must be a mapping {check, against}";
      return false;
    }
    if (!KnownKeysOnly(plots[i], kPlotKeys, path, where, error, kSweep)) return false;
    PlotSpec p;
    p.line = plots[i].Mark().line + 1;
    if (!plots[i]["check"] || !ReadText(plots[i]["check"], &p.check, &why) ||
        !(figures.count(p.check) || p.check.rfind("base_displacement", 0) == 0)) {
      *error = AtKey(path, plots[i], "check") + where + "check: must be one of the scenario's checks or a run's figure (" +
               JoinNames(figures) + ")";
      return false;
    }
    if (!plots[i]["against"] || !ReadText(plots[i]["against"], &p.against, &why) || !keys.count(p.against)) {
      *error = AtKey(path, plots[i], "against") + where + "against: must be one of the parameters (" + JoinNames(keys) + ")";
      return false;
    }
    s->plots.push_back(p);
  }
  return true;
}

// the file's stages in order: name, scenario, time limit, set, parameters, the grid, every
// variant's scenario, plots
bool ReadSweep(const YAML::Node& root, const std::string& path, const std::string& source_dir,
               SweepSpec* out, std::string* error) {
  if (!root.IsMap()) {
    *error = "sweep '" + path + "' is " + (root.IsNull() ? "empty" : "not a YAML mapping") + " (see docs/sweep.md)";
    return false;
  }
  if (!KnownKeysOnly(root, kTopKeys, path, "", error, kSweep)) return false;
  SweepSpec s;
  s.file = path;
  std::vector<std::vector<size_t>> axes;
  std::set<std::string> keys;
  if (!ReadName(root, path, &s, error) || !ReadScenarioFile(root, path, source_dir, &s, error) ||
      !ReadTimeLimit(root, path, &s, error) || !ReadSet(root, path, &s, error) ||
      !ReadParameters(root, path, &s, &axes, &keys, error) || !BuildGrid(root, path, axes, &s, error))
    return false;
  double duration = 0;
  if (!CheckVariants(&s, root, &duration, error)) return false;
  // the figures a plot may use: the base variant's checks and a run's
  std::string why;
  runner::Scenario base;
  runner::ParseScenario(s.variant_scenarios[0], s.scenario_file, &base, &why);
  std::set<std::string> figures = kRunFigures;
  figures.insert("sim_host_completed");
  for (const auto& c : base.checks) figures.insert(c.type);
  if (!ReadPlots(root, path, figures, keys, &s, error)) return false;
  if (s.time_limit <= 0) s.time_limit = 60 + 30 * duration;  // ohrp_run's own default
  *out = s;
  return true;
}

}  // namespace

bool ParseSweep(const std::string& text, const std::string& path, const std::string& source_dir,
                SweepSpec* out, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    *error = "cannot read sweep '" + path + "': " + e.what();
    return false;
  }
  return ReadSweep(root, path, source_dir, out, error);
}

bool LoadSweep(const std::string& path, const std::string& source_dir, SweepSpec* out,
               std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read sweep '" + path + "': no such file";
    return false;
  }
  std::stringstream ss;
  ss << in.rdbuf();
  return ParseSweep(ss.str(), path, source_dir, out, error);
}

}  // namespace ohrp::sweep
