// The soles' parameters from a file (see params_file.h).
#include "contact/params_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>

#include "cli/yaml_file.h"

namespace ohrp::contact {
namespace {

std::string At(const std::string& path, const YAML::Node& n) {
  return path + ":" + std::to_string(n.Mark().line + 1) + ": ";
}

}  // namespace

bool ReadContactFile(const std::string& path, SoftContactParams* p, std::vector<std::string>* keys,
                     std::string* error, const std::set<std::string>& keep) {
  YAML::Node root;
  if (!cli::LoadYamlFile(path, "contact file", &root, error)) return false;
  if (!root.IsMap() || !root["contact_params"] || !root["contact_params"].IsMap()) {
    *error = path + ": wants a mapping 'contact_params:' of the soles' parameters, e.g. "
             "contact_params: {stiffness: 2.0e6, damping: 45}";
    return false;
  }
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (key != "contact_params" && key != "identified") {
      *error = At(path, kv.first) + key + ": unknown key (contact_params, identified)";
      return false;
    }
  }
  SoftContactParams q = *p;
  const std::map<std::string, double*> fields = {
      {"stiffness", &q.stiffness},   {"exponent", &q.exponent},
      {"damping", &q.damping},       {"friction", &q.friction},
      {"tangential_stiffness", &q.tangential_stiffness},
      {"tangential_damping", &q.tangential_damping}};
  std::vector<std::string> set;
  for (const auto& kv : root["contact_params"]) {
    const std::string key = kv.first.Scalar();
    const auto it = fields.find(key);
    std::string why;
    double v = 0;
    if (it == fields.end()) {
      why = "unknown key (stiffness, exponent, damping, friction, tangential_stiffness, tangential_damping)";
    } else {
      try {
        v = kv.second.as<double>();
      } catch (const YAML::Exception&) {
        why = "'" + kv.second.Scalar() + "' is not a number";
      }
      if (why.empty() && !(std::isfinite(v) && v > 0)) why = "must be a number > 0, not " + kv.second.Scalar();
      if (why.empty() && key == "exponent" && (v < 1 || v > 3)) why = "must be in [1, 3], not " + kv.second.Scalar();
    }
    if (!why.empty()) {
      *error = At(path, kv.first) + "contact_params: " + key + ": " + why;
      return false;
    }
    if (keep.count(key)) continue;
    *it->second = v;
    set.push_back(key);
  }
  *p = q;
  *keys = set;
  return true;
}

}  // namespace ohrp::contact
