// The names a scenario gives (joints, sensors, bodies, geoms, cameras) checked against its scene's
// model before anything runs (see runner.h, CheckScenarioNames).
#include <mujoco/mujoco.h>

#include <algorithm>
#include <string>
#include <vector>

#include "runner/checks.h"
#include "runner/runner.h"
#include "robot_model/model.h"
#include "robot_model/sensors.h"
#include "robot_model/servo.h"

namespace ohrp::runner {
namespace {

// "a, b, c" (the first few of `names`)
std::string Listed(const std::vector<std::string>& names) {
  std::string s;
  for (size_t i = 0; i < names.size() && i < 40; ++i) s += (i ? ", " : "") + names[i];
  if (names.size() > 40) s += ", ...";
  return s;
}

std::vector<std::string> Named(const mjModel* m, int type, int count) {
  std::vector<std::string> out;
  for (int i = 0; i < count; ++i) {
    const char* n = mj_id2name(m, type, i);
    if (n && *n) out.push_back(n);
  }
  return out;
}

// "scenario 'FILE': line N: KEY: "
std::string At(const Scenario& s, int line, const std::string& key) {
  return "scenario '" + s.file + "': " + (line > 0 ? "line " + std::to_string(line) + ": " : "") +
         key + ": ";
}

}  // namespace

bool CheckScenarioNames(const Scenario& s, const std::string& scene, std::string* error) {
  model::InstallMujocoHandlers(nullptr);
  auto loaded = model::Scene::Load(scene, error);
  if (!loaded) return false;
  const mjModel* m = loaded->m();
  model::RobotMap robot;
  if (!model::MapRobot(m, &robot, error)) {
    *error = "scene '" + scene + "': " + *error;
    return false;
  }
  std::vector<std::string> joints, sensors;
  for (const auto& j : robot.joints) joints.push_back(j.name);
  for (const auto& j : robot.passive) joints.push_back(j.name);  // logged and plotted too
  for (const auto& f : robot.forces) sensors.push_back(f.name);
  const std::vector<std::string> bodies = Named(m, mjOBJ_BODY, m->nbody);
  const std::vector<std::string> geoms = Named(m, mjOBJ_GEOM, m->ngeom);
  const std::vector<std::string> cameras = Named(m, mjOBJ_CAMERA, m->ncam);
  // each name of `names` is one of `known` (what: "joint"); false with the file, line and key
  auto all_in = [&](const std::vector<std::string>& names, const std::vector<std::string>& known,
                    const char* what, int line, const std::string& key) {
    for (size_t k = 0; k < names.size(); ++k) {
      if (std::find(known.begin(), known.end(), names[k]) != known.end()) continue;
      *error = At(s, line, key + "[" + std::to_string(k) + "]") + "'" + names[k] + "' is not a " +
               what + " of the robot in '" + scene + "' (its " + what + "s: " + Listed(known) + ")";
      return false;
    }
    return true;
  };
  auto line = [&](const char* key) {
    const auto it = s.lines.find(key);
    return it == s.lines.end() ? 0 : it->second;
  };
  if (!all_in(s.plot_joints, joints, "joint", line("plot_joints"), "plot_joints") ||
      !all_in(s.plot_torques, joints, "joint", line("plot_torques"), "plot_torques") ||
      !all_in(s.fall_allow_contact, bodies, "body", line("fall_allow_contact"), "fall_allow_contact"))
    return false;
  for (const auto& [name, values] : s.joint_params) {
    if (std::find(joints.begin(), joints.end(), name) != joints.end()) continue;
    *error = At(s, line("joint_params"), "joint_params: " + name) + "'" + name +
             "' is not a joint of the robot in '" + scene + "' (its joints: " + Listed(joints) + ")";
    return false;
  }
  for (size_t i = 0; i < s.checks.size(); ++i) {
    const CheckSpec& c = s.checks[i];
    const std::string key = "checks[" + std::to_string(i) + "] (" + c.type + ")";
    auto param = [&](const char* name) {
      const auto it = c.params.find(name);
      return it == c.params.end() ? std::vector<std::string>{} : SplitList(it->second);
    };
    if (!all_in(param("sensors"), sensors, "force sensor", c.line, key + ": sensors") ||
        !all_in(param("sensor"), sensors, "force sensor", c.line, key + ": sensor") ||
        !all_in(param("geom"), geoms, "geom", c.line, key + ": geom") ||
        !all_in(param("camera"), cameras, "camera", c.line, key + ": camera"))
      return false;
  }
  return true;
}

}  // namespace ohrp::runner
