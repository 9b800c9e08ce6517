// The joints as identified, read and written (see joint_params.h; applied to a model:
// joint_params_apply.cc, the one part that calls MuJoCo).
#include "robot_model/joint_params.h"

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <set>
#include <sstream>

#include "cli/yaml_file.h"

namespace ohrp::model {
namespace {

std::string At(const std::string& path, const YAML::Node& n) {
  return path + ":" + std::to_string(n.Mark().line + 1) + ": ";
}

// one key of a joint's entry: a finite number in [0, max]
bool ReadValue(const std::string& path, const std::string& joint, const YAML::Node& key,
               const YAML::Node& value, double max, double* out, std::string* error) {
  const std::string where = At(path, key) + "joints: " + joint + ": " + key.Scalar() + ": ";
  double v = 0;
  if (!value.IsScalar() || !YAML::convert<double>::decode(value, v)) {
    *error = where + "'" + (value.IsScalar() ? value.Scalar() : std::string("(not a scalar)")) +
             "' is not a number";
    return false;
  }
  if (!(std::isfinite(v) && v >= 0 && v <= max)) {
    std::ostringstream s;
    s << where << "must be in [0, " << max << "], not " << value.Scalar();
    *error = s.str();
    return false;
  }
  *out = v;
  return true;
}

bool ReadEntry(const std::string& path, const YAML::Node& name, const YAML::Node& entry,
               JointParams* p, std::string* error) {
  p->joint = name.Scalar();
  if (!entry.IsMap() || entry.size() == 0) {
    *error = At(path, name) + "joints: " + p->joint +
             ": wants a mapping of armature, damping, frictionloss and/or delay, e.g. {damping: 2.0}";
    return false;
  }
  for (const auto& kv : entry) {
    const std::string key = kv.first.Scalar();
    bool ok = false;
    if (key == "armature")
      ok = ReadValue(path, p->joint, kv.first, kv.second, kMaxArmature, &p->armature, error);
    else if (key == "damping")
      ok = ReadValue(path, p->joint, kv.first, kv.second, kMaxDamping, &p->damping, error);
    else if (key == "frictionloss")
      ok = ReadValue(path, p->joint, kv.first, kv.second, kMaxFrictionloss, &p->frictionloss, error);
    else if (key == "delay")
      ok = ReadValue(path, p->joint, kv.first, kv.second, kMaxDelay, &p->delay, error);
    else
      *error = At(path, kv.first) + "joints: " + p->joint + ": " + key +
               ": unknown key (armature, damping, frictionloss, delay)";
    if (!ok) return false;
  }
  return true;
}

void Put(std::ostringstream& s, const char* key, double v, bool* first) {
  if (std::isnan(v)) return;
  s << (*first ? "" : ", ") << key << ": " << v;
  *first = false;
}

}  // namespace

bool ReadJointParamsFile(const std::string& path, std::vector<JointParams>* joints,
                         std::string* error) {
  YAML::Node root;
  if (!cli::LoadYamlFile(path, "joint file", &root, error)) return false;
  if (!root.IsMap() || !root["joints"] || !root["joints"].IsMap() || root["joints"].size() == 0) {
    *error = path + ": wants a mapping 'joints:' of joints, e.g. "
             "joints: {LARM_ELBOW: {armature: 15.0, damping: 2.0, frictionloss: 1.5}}";
    return false;
  }
  for (const auto& kv : root) {
    if (kv.first.Scalar() != "joints") {
      *error = At(path, kv.first) + kv.first.Scalar() + ": unknown key (joints)";
      return false;
    }
  }
  std::vector<JointParams> out;
  std::set<std::string> seen;
  for (const auto& kv : root["joints"]) {
    JointParams p;
    if (!ReadEntry(path, kv.first, kv.second, &p, error)) return false;
    if (!seen.insert(p.joint).second) {
      *error = At(path, kv.first) + "joints: " + p.joint + ": given twice";
      return false;
    }
    out.push_back(p);
  }
  *joints = std::move(out);
  return true;
}

bool WriteJointParamsFile(const std::string& path, const std::vector<JointParams>& joints,
                          const std::vector<std::string>& header, std::string* error) {
  std::ostringstream s;
  s.precision(6);
  for (const std::string& h : header) s << "# " << h << "\n";
  s << "joints:\n";
  for (const JointParams& p : joints) {
    s << "  " << p.joint << ": {";
    bool first = true;
    Put(s, "armature", p.armature, &first);
    Put(s, "damping", p.damping, &first);
    Put(s, "frictionloss", p.frictionloss, &first);
    Put(s, "delay", p.delay, &first);
    s << "}";
    if (!p.note.empty()) s << "  # " << p.note;
    s << "\n";
  }
  std::ofstream f(path);
  f << s.str();
  f.close();
  if (!f) {
    *error = "cannot write " + path;
    return false;
  }
  return true;
}

std::string DescribeJointParams(const std::vector<JointParams>& joints) {
  std::ostringstream s;
  s.precision(4);
  for (size_t i = 0; i < joints.size(); ++i) {
    const JointParams& p = joints[i];
    s << (i ? "; " : "") << p.joint;
    if (!std::isnan(p.armature)) s << " armature " << p.armature;
    if (!std::isnan(p.damping)) s << " damping " << p.damping;
    if (!std::isnan(p.frictionloss)) s << " frictionloss " << p.frictionloss;
    if (!std::isnan(p.delay)) s << " delay " << p.delay << " s";
  }
  return s.str();
}

bool JointDelayCycles(const std::vector<JointParams>& joints, const std::vector<std::string>& joint_names,
                      double period, std::vector<int>* cycles, std::string* error) {
  cycles->assign(joint_names.size(), 0);
  for (const JointParams& p : joints) {
    if (std::isnan(p.delay)) continue;
    const double n = p.delay / period;
    if (std::fabs(n - std::round(n)) > 1e-6) {
      std::ostringstream s;
      s << "joints: " << p.joint << ": delay " << p.delay << " s is not a whole number of control periods ("
        << period << " s): e.g. " << std::floor(n) * period << " or " << std::ceil(n) * period;
      *error = s.str();
      return false;
    }
    for (size_t j = 0; j < joint_names.size(); ++j)
      if (joint_names[j] == p.joint) (*cycles)[j] = static_cast<int>(std::lround(n));
  }
  return true;
}

}  // namespace ohrp::model
