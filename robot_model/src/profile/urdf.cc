// A URDF robot under a robot profile (see urdf.h).
#include "profile/urdf.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "robot_model/load.h"

namespace ohrp::model::profile {

using mjcf::Number;
using mjcf::Tree;

// a URDF compiled by MuJoCo and saved as MJCF (mj_saveLastXML writes a file: a temporary one in
// $TMPDIR, removed at once; never beside the model). MuJoCo fuses a URDF's static links into the
// world, its root link too: the URDF is compiled with fusestatic="false" (MuJoCo's <mujoco>
// extension element, added in memory unless the author wrote one), so that the root link stays
// a body that `base: free` can float.
bool UrdfText(const std::string& path, std::string* text, std::string* error) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream read;
  read << file.rdbuf();
  std::string urdf = read.str();
  const size_t robot = urdf.find("<robot");
  const size_t open = robot == std::string::npos ? robot : urdf.find('>', robot);
  if (!file || open == std::string::npos) {
    *error = "cannot read URDF '" + path + "' (no <robot> element)";
    return false;
  }
  if (urdf.find("<mujoco") == std::string::npos)
    urdf.insert(open + 1, "<mujoco><compiler fusestatic=\"false\"/></mujoco>");
  const std::filesystem::path p(path);
  ModelPtr m(LoadMjcfText(urdf, (p.parent_path() / ("ohrp_profile_" + p.stem().string() + ".urdf")).string(),
                          "URDF '" + path + "'", error));
  if (!m) return false;
  char err[1024] = "";
  const char* tmpdir = std::getenv("TMPDIR");
  std::string name = std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/ohrp_urdf_XXXXXX.xml";
  const int fd = mkstemps(name.data(), 4);
  if (fd < 0) {
    *error = "cannot make a temporary file for the MJCF of URDF '" + path + "'";
    return false;
  }
  close(fd);
  const bool saved = mj_saveLastXML(name.c_str(), m.get(), err, sizeof err) != 0;
  std::ifstream in(name, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  std::remove(name.c_str());
  if (!saved || s.str().empty()) {
    *error = "cannot save the MJCF of URDF '" + path + "': " + err;
    return false;
  }
  *text = s.str();
  return true;
}

// a URDF robot made whole before anything is derived: a free joint on the root body, one
// actuator per joint (profile keys base, actuators)
bool PrepareRobot(const RobotProfile& p, const mjModel* m, Tree* root, std::string* error) {
  std::vector<std::string> missing;
  if (p.free_base) {
    Tree* world = mjcf::NthChild(root, "worldbody", 0);
    Tree* base = world ? mjcf::NthChild(world, "body", 0) : nullptr;
    bool has_free = false;
    for (int j = 0; j < m->njnt; ++j) has_free = has_free || m->jnt_type[j] == mjJNT_FREE;
    if (!base) missing.push_back("base: free: the model has no body under <worldbody>");
    else if (has_free) missing.push_back("base: free: the model has a free joint already");
    else mjcf::SetAttr(&mjcf::Append(base, "freejoint"), "name", "base_free");
  }
  if (!p.actuator_type.empty()) {
    std::vector<std::string> joints = p.actuator_joints;
    if (joints.empty())
      for (int j = 0; j < m->njnt; ++j)
        if (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE)
          joints.push_back(mj_id2name(m, mjOBJ_JOINT, j) ? mj_id2name(m, mjOBJ_JOINT, j) : "");
    Tree& section = mjcf::Append(root, "actuator");
    for (const std::string& name : joints) {
      const int j = name.empty() ? -1 : mj_name2id(m, mjOBJ_JOINT, name.c_str());
      if (j < 0) {
        missing.push_back("actuators.joints: " + (name.empty() ? std::string("a joint without a name")
                                                               : "the model has no joint '" + name + "'"));
        continue;
      }
      for (int a = 0; a < m->nu; ++a)
        if (m->actuator_trntype[a] == mjTRN_JOINT && m->actuator_trnid[2 * a] == j)
          missing.push_back("actuators: joint '" + name + "' has an actuator already");
      Tree& act = mjcf::Append(&section, p.actuator_type);
      mjcf::SetAttr(&act, "name", name + "_" + p.actuator_type);
      mjcf::SetAttr(&act, "joint", name);
      const std::string limit = Number(-p.actuator_limit) + ' ' + Number(p.actuator_limit);
      if (p.actuator_type == "position") {
        mjcf::SetAttr(&act, "kp", Number(p.actuator_kp));
        if (p.actuator_limit > 0) {
          mjcf::SetAttr(&act, "forcelimited", "true");
          mjcf::SetAttr(&act, "forcerange", limit);
        }
      } else if (p.actuator_limit > 0) {
        mjcf::SetAttr(&act, "ctrllimited", "true");
        mjcf::SetAttr(&act, "ctrlrange", limit);
      }
    }
  }
  if (missing.empty()) return true;
  *error = "robot profile '" + p.file + "' on '" + p.model + "': " + std::to_string(missing.size()) +
           " problem" + (missing.size() > 1 ? "s" : "") + " (all listed):";
  for (const std::string& s : missing) *error += "\n  - " + s;
  return false;
}

}  // namespace ohrp::model::profile
