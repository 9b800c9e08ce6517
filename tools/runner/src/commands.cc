// The processes' command lines and their placeholders (see runner/commands.h).
#include "runner/commands.h"

#include <algorithm>
#include <cstdio>

#include "host_keys.h"

namespace ohrp::runner {
namespace {

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

}  // namespace

//---------------- placeholders ----------------

std::string UnknownPlaceholder(const std::string& arg) {
  // each `{...}` in turn: only `{out}` is known
  for (size_t open = arg.find('{'); open != std::string::npos; open = arg.find('{', open + 1)) {
    const size_t close = arg.find('}', open);
    if (close == std::string::npos) return "";
    const std::string found = arg.substr(open, close - open + 1);
    if (found != kOutPlaceholder)
      return "unknown placeholder '" + found + "' in '" + arg +
             "' (the only one is {out}, the run's output folder, e.g. \"{out}/walk.csv\")";
    open = close;
  }
  return "";
}

std::string ExpandPlaceholders(const std::string& arg, const std::string& out_dir) {
  std::string s = arg;
  const std::string key = kOutPlaceholder;
  for (size_t at = s.find(key); at != std::string::npos; at = s.find(key, at + out_dir.size()))
    s.replace(at, key.size(), out_dir);
  return s;
}

//---------------- command lines ----------------

std::vector<std::string> SimHostCommand(const Scenario& s, const std::string& sim_host,
                                        const std::string& scene, const std::string& segment,
                                        const std::string& out_dir) {
  // the run's files
  std::vector<std::string> argv = {
      sim_host, "--scene", scene, "--segment", segment,
      "--wait-controller", s.controllers.empty() ? "0" : "20",
      "--log", out_dir + "/log.csv", "--summary", out_dir + "/sim_summary.json"};
  // a self_collisions check needs sim_host's self_collision effect (the scenario's own
  // effects come later and win)
  for (const auto& c : s.checks) {
    if (c.type != "self_collisions") continue;
    argv.insert(argv.end(), {"--effects", "self_collision=on"});
    break;
  }
  // the scenario's keys that are sim_host options, from their table (cli/host_options.h)
  AppendHostOptions(s, &argv);
  // the soft soles' parameters
  for (const auto& [key, value] : s.contact_params) {
    std::string flag = "--contact-" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    argv.insert(argv.end(), {flag, Num(value)});
  }
  // the joints' parameters: the file the runner writes into the run folder (runner.cc)
  if (!s.joint_params.empty()) argv.insert(argv.end(), {"--joint-file", out_dir + "/joint_params.yaml"});
  // the scenario's own arguments
  for (const auto& a : s.sim_args) argv.push_back(ExpandPlaceholders(a, out_dir));
  return argv;
}

std::vector<std::string> ControllerCommand(const ControllerSpec& spec, const std::string& program,
                                           const std::string& segment, const std::string& out_dir) {
  std::vector<std::string> argv = {program, "--segment", segment, "--attach-timeout", "10"};
  for (const auto& a : spec.args) argv.push_back(ExpandPlaceholders(a, out_dir));
  return argv;
}

}  // namespace ohrp::runner
