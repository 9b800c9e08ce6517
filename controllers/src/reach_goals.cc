// reach's goals file (controllers/reach_goals.h).
#include "controllers/reach_goals.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>

#include "cli/yaml_file.h"

namespace ohrp::controllers {
namespace {

// "PATH:LINE: KEY: what" (LINE from the node's mark, 1-based)
struct Where {
  const std::string& path;
  std::string* error;
  bool Fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    const int line = node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
    *error = path + ":" + std::to_string(line) + ": " + key + ": " + what;
    return false;
  }
};

bool Number(const Where& w, const YAML::Node& n, const std::string& key, double lo, double hi, double* out) {
  if (!n.IsScalar()) return w.Fail(n, key, "give a number");
  try {
    *out = n.as<double>();
  } catch (const YAML::Exception&) {
    return w.Fail(n, key, "'" + n.Scalar() + "' is not a number");
  }
  if (!std::isfinite(*out) || *out < lo || *out > hi)
    return w.Fail(n, key, n.Scalar() + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return true;
}

bool Vector3(const Where& w, const YAML::Node& n, const std::string& key, double bound, Eigen::Vector3d* out) {
  if (!n.IsSequence() || n.size() != 3) return w.Fail(n, key, "give three numbers [a, b, c]");
  for (int i = 0; i < 3; ++i)
    if (!Number(w, n[i], key, -bound, bound, &(*out)[i])) return false;
  return true;
}

bool KnownKeys(const Where& w, const YAML::Node& map, const std::set<std::string>& known, const std::string& what) {
  for (const auto& kv : map) {
    const std::string k = kv.first.as<std::string>();
    if (!known.count(k)) {
      std::string list;
      for (const auto& s : known) list += (list.empty() ? "" : ", ") + s;
      return w.Fail(kv.first, k, "unknown key in " + what + " (known: " + list + ")");
    }
  }
  return true;
}

// one hand's pose {site, position, rpy} into spec->hands
bool ReadHand(const Where& w, const YAML::Node& p, GoalSpec* spec) {
  if (!p.IsMap())
    return w.Fail(p, "pose", "give {site: NAME, position: [x, y, z], rpy: [r, p, y]}, or a list of them (one per hand)");
  if (!KnownKeys(w, p, {"site", "position", "rpy"}, "a pose")) return false;
  if (!p["site"].IsDefined() || !p["site"].IsScalar()) return w.Fail(p, "pose: site", "missing (the hand's site)");
  if (!p["position"].IsDefined()) return w.Fail(p, "pose: position", "missing ([x, y, z] in the base frame, m)");
  HandGoal hand;
  hand.site = p["site"].Scalar();
  if (!Vector3(w, p["position"], "pose: position", 10, &hand.p_B)) return false;
  hand.orientation = p["rpy"].IsDefined();
  if (hand.orientation && !Vector3(w, p["rpy"], "pose: rpy", 2 * M_PI, &hand.rpy)) return false;
  spec->hands.push_back(hand);
  return true;
}

bool ReadGoal(const Where& w, const YAML::Node& g, GoalSpec* spec) {
  spec->line = g.Mark().line + 1;
  if (!g.IsMap()) return w.Fail(g, "goals", "each goal is a map with joints: or pose:");
  if (!KnownKeys(w, g, {"joints", "pose", "hold"}, "a goal")) return false;
  if (g["joints"].IsDefined() == g["pose"].IsDefined())
    return w.Fail(g, "goals", "give one of joints: {NAME: rad, ...} or pose: {site, position, rpy}");
  if (g["hold"].IsDefined() && !Number(w, g["hold"], "hold", 0, 3600, &spec->hold)) return false;
  if (const YAML::Node j = g["joints"]; j.IsDefined()) {
    if (!j.IsMap() || j.size() == 0) return w.Fail(j, "joints", "give a map NAME: radians");
    for (const auto& kv : j) {
      double v = 0;
      const std::string name = kv.first.as<std::string>();
      if (!Number(w, kv.second, "joints: " + name, -100, 100, &v)) return false;
      spec->joints.emplace_back(name, v);
    }
    return true;
  }
  // a hand's pose, or a list of them (one per limb: both hands)
  const YAML::Node poses = g["pose"];
  if (poses.IsSequence() && poses.size() > 0) {
    for (const auto& p : poses)
      if (!ReadHand(w, p, spec)) return false;
    return true;
  }
  return ReadHand(w, poses, spec);
}

}  // namespace

bool ReadGoalsFile(const std::string& path, GoalsFile* out, std::string* error) {
  *out = GoalsFile();
  out->path = path;
  YAML::Node root;
  if (!cli::LoadYamlFile(path, "goals file", &root, error)) return false;
  const Where w{path, error};
  if (!root.IsMap()) return w.Fail(root, "goals", "the file is a map with goals: (and group:)");
  if (!KnownKeys(w, root, {"group", "goals"}, "the file")) return false;
  if (const YAML::Node g = root["group"]; g.IsDefined()) {
    if (!g.IsSequence() || g.size() == 0) return w.Fail(g, "group", "give a list of joint names");
    for (const auto& n : g) out->group.push_back(n.as<std::string>());
  }
  const YAML::Node goals = root["goals"];
  if (!goals.IsDefined()) return w.Fail(root, "goals", "missing (a list of goals)");
  if (!goals.IsSequence() || goals.size() == 0) return w.Fail(goals, "goals", "give a list of at least one goal");
  for (const auto& g : goals) {
    GoalSpec spec;
    if (!ReadGoal(w, g, &spec)) return false;
    out->goals.push_back(spec);
  }
  if (out->group.empty() && !out->goals[0].hands.empty())
    return w.Fail(goals[0], "group", "missing: a pose goal needs the group (the joints the plan moves)");
  return true;
}

}  // namespace ohrp::controllers
