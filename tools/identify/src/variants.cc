// The default RunVariant: one ohrp_run of the scenario with the soles' K and D (see identify.h).
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "identify/identify.h"

namespace ohrp::identify {

namespace {

std::string Quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.9g", v);
  return buf;
}

}  // namespace

RunVariant OhrpRunVariant(const std::string& ohrp_run, const std::string& scenario) {
  return [=](double k, double d, const std::string& dir, std::string* log, std::string* error) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    YAML::Node s;
    try {
      s = YAML::LoadFile(scenario);
    } catch (const std::exception& e) {
      *error = scenario + ": " + e.what();
      return false;
    }
    // relative paths of the scenario (scene, controllers' files) are the repository's, as
    // ohrp_run resolves them: the copy may live anywhere
    YAML::Node args = s["sim_args"];
    if (!args || !args.IsSequence()) args = YAML::Node(YAML::NodeType::Sequence);
    for (const std::string& a : {std::string("--contact-stiffness"), Number(k),
                                 std::string("--contact-damping"), Number(d)})
      args.push_back(a);
    s["sim_args"] = args;
    s["name"] = s["name"].as<std::string>("variant") + "_k" + Number(k) + "_d" + Number(d);
    const std::string copy = dir + "/scenario.yaml";
    {
      std::ofstream f(copy);
      f << s << "\n";
    }
    const std::string cmd = Quote(ohrp_run) + " " + Quote(copy) + " --out " + Quote(dir + "/run") +
                            " --no-plot -q > " + Quote(dir + "/run.txt") + " 2>&1";
    const int rc = std::system(cmd.c_str());
    *log = dir + "/run/log.csv";
    if (!fs::exists(*log)) {
      *error = "the simulation with K = " + Number(k) + " N/m, D = " + Number(d) +
               " s/m wrote no log (exit " + std::to_string(rc) + "; see " + dir + "/run.txt)";
      return false;
    }
    return true;
  };
}

}  // namespace ohrp::identify
