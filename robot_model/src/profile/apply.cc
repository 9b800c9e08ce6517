// Applying a robot profile to its model in memory (see robot_model/profile.h): the model read
// with its includes expanded, compiled once as the author wrote it (what to derive, what is
// missing), the profile's additions made in the XML tree, the result given back as MJCF text.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "profile/derive.h"
#include "profile/mjcf_tree.h"
#include "profile/urdf.h"
#include "robot_model/load.h"
#include "robot_model/profile.h"
#include "vrml/vrml.h"

namespace ohrp::model {
namespace {

using mjcf::Tree;

using mjcf::Number;

template <typename V>
std::string Nums(const V& v, size_t n) {
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    if (i) s += ' ';
    s += Number(v[i]);
  }
  return s;
}

bool EndsWithCi(const std::string& s, const std::string& suffix) {
  if (s.size() < suffix.size()) return false;
  for (size_t i = 0; i < suffix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[s.size() - suffix.size() + i])) != suffix[i]) return false;
  return true;
}

// the model's MJCF text (a VRML file converted, a URDF compiled and saved as MJCF)
bool ModelText(const std::string& path, std::string* text, std::string* error) {
  if (vrml::IsVrmlPath(path)) return vrml::ConvertFile(path, text, error);
  if (EndsWithCi(path, ".urdf")) return profile::UrdfText(path, text, error);
  std::ifstream in(path, std::ios::binary);
  std::error_code ec;
  if (!in || !std::filesystem::is_regular_file(path, ec)) {
    *error = "cannot read model '" + path + "'";
    return false;
  }
  std::ostringstream s;
  s << in.rdbuf();
  *text = s.str();
  return true;
}

// what the profile adds, decided on the compiled original before the tree is touched
struct Plan {
  struct Sole {
    std::string name, body;
    std::array<double, 2> size{};
    std::array<double, 3> centre{};
    std::vector<int> own_geoms;  // the foot body's colliding geoms (index within the body)
  };
  struct Site {
    std::string name, body;
    std::array<double, 3> pos{};
  };
  std::vector<Sole> soles;
  std::vector<Sole> own_soles;  // the model's own *_SOLE boxes (for the stance's height)
  std::vector<Site> force_torque;
  std::vector<Site> imu;  // 0 or 1
  bool key = false;
  std::vector<double> key_qpos, key_ctrl;
};

class Planner {
 public:
  Planner(const RobotProfile& p, const mjModel* m) : p_(p), m_(m) {}

  bool Make(Plan* plan, std::string* error) {
    for (const ProfileFoot& f : p_.feet) Foot(f, plan);
    Imu(plan);
    Stand(plan);
    for (const auto* lists : {&p_.chains, &p_.groups})
      for (const auto& [name, joints] : *lists)
        for (const std::string& j : joints)
          if (mj_name2id(m_, mjOBJ_JOINT, j.c_str()) < 0)
            Missing(name + ": the model has no joint '" + j + "'");
    if (missing_.empty()) return true;
    *error = "robot profile '" + p_.file + "' on '" + p_.model + "': " +
             std::to_string(missing_.size()) + " problem" + (missing_.size() > 1 ? "s" : "") +
             " (all listed):";
    for (const std::string& s : missing_) *error += "\n  - " + s;
    return false;
  }

 private:
  void Missing(const std::string& s) { missing_.push_back(s); }

  // a name the profile adds must be new
  bool Fresh(int type, const std::string& name, const char* what) {
    if (mj_name2id(m_, type, name.c_str()) < 0) return true;
    Missing(std::string("the model already has a ") + what + " named '" + name +
            "' (the profile adds one of that name)");
    return false;
  }

  int Body(const std::string& name, const std::string& key) {
    const int b = mj_name2id(m_, mjOBJ_BODY, name.c_str());
    if (b < 0) Missing(key + ": the model has no body '" + name + "'");
    return b;
  }

  void Foot(const ProfileFoot& f, Plan* plan) {
    const std::string key = "feet." + f.side;
    const int b = Body(f.body, key + ".body");
    if (b < 0) return;
    if (const int g = profile::SoleGeom(m_, b); g >= 0) {  // the model's own *_SOLE box
      if (f.sole_given)
        Missing(key + ".sole: body '" + f.body + "' has its own sole box '" +
                mj_id2name(m_, mjOBJ_GEOM, g) + "'; leave sole out");
      const mjtNum* size = m_->geom_size + 3 * g;
      const mjtNum* pos = m_->geom_pos + 3 * g;
      plan->own_soles.push_back({"", f.body, {2 * size[0], 2 * size[1]}, {pos[0], pos[1], pos[2] - size[2]}, {}});
      ForceTorque(f, b, plan);
      return;
    }
    Plan::Sole s;
    s.name = f.side == "left" ? "LEFT_SOLE" : "RIGHT_SOLE";
    s.body = f.body;
    if (f.sole_given) {
      s.size = f.size;
      s.centre = f.centre;
    } else {
      std::string how;
      if (!profile::DeriveSole(m_, b, &s.size, &s.centre, &how))
        Missing(key + ".sole: cannot be derived from body '" + f.body + "' (" + how +
                "); give size [x, y] and centre [x, y, z] in the body's frame");
    }
    if (p_.contact == "soft") {
      for (int k = 0; k < m_->body_geomnum[b]; ++k)
        if (profile::Collides(m_, m_->body_geomadr[b] + k)) s.own_geoms.push_back(k);
    }
    if (Fresh(mjOBJ_GEOM, s.name, "geom")) plan->soles.push_back(s);
    ForceTorque(f, b, plan);
  }

  void ForceTorque(const ProfileFoot& f, int b, Plan* plan) {
    // the F/T sensor: where the profile says, else on the foot body when the foot has none
    const auto given = p_.force_torque_sites.find(f.side);
    if (given == p_.force_torque_sites.end() && (!p_.force_torque || profile::HasForceTorque(m_, b)))
      return;
    Plan::Site site{f.side + "_foot_ft", f.body, {0, 0, 0}};
    if (given != p_.force_torque_sites.end()) {
      if (!given->second.body.empty()) site.body = given->second.body;
      site.pos = given->second.pos;
      if (Body(site.body, "force_torque." + f.side + ".body") < 0) return;
    }
    if (Fresh(mjOBJ_SITE, site.name, "site") && Fresh(mjOBJ_SENSOR, site.name + "_force", "sensor") &&
        Fresh(mjOBJ_SENSOR, site.name + "_torque", "sensor"))
      plan->force_torque.push_back(site);
  }

  void Imu(Plan* plan) {
    if (!p_.imu_given && (!p_.imu || profile::ImuSite(m_) >= 0)) return;
    Plan::Site site{"profile_imu", p_.imu_site.body, p_.imu_site.pos};
    if (site.body.empty()) {
      const int root = profile::RootBody(m_);
      if (root < 0) return Missing("imu: the model has no body to carry an IMU");
      site.body = mj_id2name(m_, mjOBJ_BODY, root) ? mj_id2name(m_, mjOBJ_BODY, root) : "";
      if (site.body.empty()) return Missing("imu: the root body has no name; give imu.body");
    } else if (Body(site.body, "imu.body") < 0) {
      return;
    }
    if (Fresh(mjOBJ_SITE, site.name, "site")) plan->imu.push_back(site);
  }

  void Stand(Plan* plan) {
    if (!p_.stand_keyframe.empty()) {
      const int k = mj_name2id(m_, mjOBJ_KEY, p_.stand_keyframe.c_str());
      if (k < 0) return Missing("stand.keyframe: the model has no keyframe '" + p_.stand_keyframe + "'");
      if (p_.stand_keyframe == "stand") return;  // already the stance
      plan->key = true;
      plan->key_qpos.assign(m_->key_qpos + k * m_->nq, m_->key_qpos + (k + 1) * m_->nq);
      plan->key_ctrl.assign(m_->key_ctrl + k * m_->nu, m_->key_ctrl + (k + 1) * m_->nu);
      return;
    }
    if (p_.stand_joints.empty()) return;
    std::vector<double> q(m_->qpos0, m_->qpos0 + m_->nq);
    for (const auto& [name, value] : p_.stand_joints) {
      const int j = mj_name2id(m_, mjOBJ_JOINT, name.c_str());
      if (j < 0 || (m_->jnt_type[j] != mjJNT_HINGE && m_->jnt_type[j] != mjJNT_SLIDE)) {
        Missing("stand.joints." + name + ": the model has no hinge or slide joint of that name");
        continue;
      }
      q[m_->jnt_qposadr[j]] = value;
    }
    // the servos' targets: a position-type actuator (affine bias) holds its joint's stance
    std::vector<double> ctrl(m_->nu, 0.0);
    for (int a = 0; a < m_->nu; ++a) {
      if (m_->actuator_trntype[a] == mjTRN_JOINT && m_->actuator_biastype[a] == mjBIAS_AFFINE)
        ctrl[a] = q[m_->jnt_qposadr[m_->actuator_trnid[2 * a]]];
    }
    const int root = profile::RootBody(m_);
    const bool free = root >= 0 && m_->body_jntnum[root] > 0 &&
                      m_->jnt_type[m_->body_jntadr[root]] == mjJNT_FREE;
    if (free) {
      const int adr = m_->jnt_qposadr[m_->body_jntadr[root]];
      if (p_.stand_height_given) {
        q[adr + 2] = p_.stand_height;
      } else if (!plan->soles.empty() || !plan->own_soles.empty()) {
        q[adr + 2] -= LowestSole(q, *plan);  // the lowest sole's bottom at z = 0
      }
    }
    plan->key = true;
    plan->key_qpos = q;
    plan->key_ctrl = ctrl;
  }

  // the lowest z of the soles' bottom corners at configuration q
  double LowestSole(const std::vector<double>& q, const Plan& plan) const {
    mjData* d = mj_makeData(m_);
    std::copy(q.begin(), q.end(), d->qpos);
    mj_kinematics(m_, d);
    double low = INFINITY;
    std::vector<Plan::Sole> all = plan.soles;
    all.insert(all.end(), plan.own_soles.begin(), plan.own_soles.end());
    for (const Plan::Sole& s : all) {
      const int b = mj_name2id(m_, mjOBJ_BODY, s.body.c_str());
      for (int k = 0; k < 4; ++k) {
        const mjtNum local[3] = {s.centre[0] + (k & 1 ? 0.5 : -0.5) * s.size[0],
                                 s.centre[1] + (k & 2 ? 0.5 : -0.5) * s.size[1], s.centre[2]};
        mjtNum w[3];
        mju_rotVecMat(w, local, d->xmat + 9 * b);
        low = std::min(low, d->xpos[3 * b + 2] + w[2]);
      }
    }
    mj_deleteData(d);
    return low;
  }

  const RobotProfile& p_;
  const mjModel* m_;
  std::vector<std::string> missing_;
};

void AddSite(Tree* root, const Plan::Site& s) {
  Tree* body = mjcf::FindBody(root, s.body);
  Tree& site = mjcf::Append(body, "site");
  mjcf::SetAttr(&site, "name", s.name);
  mjcf::SetAttr(&site, "pos", Nums(s.pos, 3));
  mjcf::SetAttr(&site, "size", "0.01");
}

void AddSensor(Tree* sensors, const char* type, const std::string& site, const std::string& name) {
  Tree& e = mjcf::Append(sensors, type);
  mjcf::SetAttr(&e, "name", name);
  mjcf::SetAttr(&e, type == std::string("framequat") ? "objname" : "site", site);
  if (type == std::string("framequat")) mjcf::SetAttr(&e, "objtype", "site");
}

// the plan's additions made in the tree; false when a body is not an element of it
bool Edit(const RobotProfile& p, const Plan& plan, Tree* root, std::string* error) {
  for (const auto* sites : {&plan.force_torque, &plan.imu})
    for (const Plan::Site& s : *sites)
      if (!mjcf::FindBody(root, s.body)) {
        *error = "robot profile '" + p.file + "': body '" + s.body + "' is not a <body> element of '" +
                 p.model + "' (made by a construct the profile cannot edit)";
        return false;
      }
  for (const Plan::Sole& s : plan.soles) {
    Tree* body = mjcf::FindBody(root, s.body);
    if (!body) {
      *error = "robot profile '" + p.file + "': body '" + s.body + "' is not a <body> element of '" +
               p.model + "'";
      return false;
    }
    for (int k : s.own_geoms) {  // soft: the sole replaces the foot's own contact
      Tree* g = mjcf::NthChild(body, "geom", k);
      mjcf::SetAttr(g, "contype", "0");
      mjcf::SetAttr(g, "conaffinity", "0");
    }
    const double half_t = 0.5 * p.sole_thickness;
    Tree& g = mjcf::Append(body, "geom");
    mjcf::SetAttr(&g, "name", s.name);
    mjcf::SetAttr(&g, "type", "box");
    mjcf::SetAttr(&g, "size", Nums(std::array<double, 3>{0.5 * s.size[0], 0.5 * s.size[1], half_t}, 3));
    mjcf::SetAttr(&g, "pos", Nums(std::array<double, 3>{s.centre[0], s.centre[1], s.centre[2] + half_t}, 3));
    const char* collide = p.contact == "soft" ? "1" : "0";
    mjcf::SetAttr(&g, "contype", collide);
    mjcf::SetAttr(&g, "conaffinity", collide);
    mjcf::SetAttr(&g, "condim", "3");
    mjcf::SetAttr(&g, "density", "0");
    mjcf::SetAttr(&g, "group", "4");
    mjcf::SetAttr(&g, "rgba", "0 0.5 0 0.4");
  }
  for (const Plan::Site& s : plan.force_torque) AddSite(root, s);
  for (const Plan::Site& s : plan.imu) AddSite(root, s);
  if (!plan.force_torque.empty() || !plan.imu.empty()) {
    Tree& sensors = mjcf::Append(root, "sensor");
    for (const Plan::Site& s : plan.force_torque) {
      AddSensor(&sensors, "force", s.name, s.name + "_force");
      AddSensor(&sensors, "torque", s.name, s.name + "_torque");
    }
    for (const Plan::Site& s : plan.imu) {
      AddSensor(&sensors, "gyro", s.name, s.name + "_gyro");
      AddSensor(&sensors, "accelerometer", s.name, s.name + "_accel");
      AddSensor(&sensors, "framequat", s.name, s.name + "_quat");
    }
  }
  if (plan.key) {
    mjcf::RemoveKey(root, "stand");
    Tree& key = mjcf::Append(&mjcf::Append(root, "keyframe"), "key");
    mjcf::SetAttr(&key, "name", "stand");
    mjcf::SetAttr(&key, "qpos", Nums(plan.key_qpos, plan.key_qpos.size()));
    if (!plan.key_ctrl.empty()) mjcf::SetAttr(&key, "ctrl", Nums(plan.key_ctrl, plan.key_ctrl.size()));
  }
  return true;
}

}  // namespace

bool ApplyProfile(const RobotProfile& p, std::string* mjcf_text, std::string* vfs_name,
                  std::string* error) {
  std::string text;
  if (!ModelText(p.model, &text, error)) {
    *error = "robot profile '" + p.file + "': model: " + *error;
    return false;
  }
  Tree doc;
  if (!mjcf::ReadExpanded(text, p.model, &doc, error)) return false;
  // a name in the model's own folder, which nothing is written to (MuJoCo's VFS holds it)
  const std::filesystem::path model(p.model);
  *vfs_name = (model.parent_path() / ("ohrp_profile_" + model.stem().string() + ".xml")).string();
  if (p.free_base || !p.actuator_type.empty()) {
    ModelPtr bare(LoadMjcfText(mjcf::Write(doc), *vfs_name, "'" + p.model + "'", error));
    if (!bare || !profile::PrepareRobot(p, bare.get(), &doc.begin()->second, error)) return false;
  }
  ModelPtr original(LoadMjcfText(mjcf::Write(doc), *vfs_name, "'" + p.model + "'", error));
  if (!original) return false;
  Plan plan;
  if (!Planner(p, original.get()).Make(&plan, error)) return false;
  if (!Edit(p, plan, &doc.begin()->second, error)) return false;
  *mjcf_text = mjcf::Write(doc);
  return true;
}

}  // namespace ohrp::model
