// A draft robot profile from a model's tree (see robot_model/profile.h: DraftProfile): the feet
// are the lowest bodies of two branches of the tree, their soles the lowest geoms, the legs the
// joints from the root to each foot, the IMU an existing gyro + accelerometer site or the root,
// the stance a keyframe. Every value says where it came from, for the user to review.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "profile/derive.h"
#include "robot_model/load.h"
#include "robot_model/profile.h"

namespace ohrp::model {
namespace {

std::string Name(const mjModel* m, int type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "";
}

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4f", std::abs(v) < 5e-5 ? 0.0 : v);
  return b;
}

bool IsAncestor(const mjModel* m, int a, int b) {  // a is b or one of b's ancestors
  for (; b > 0; b = m->body_parentid[b])
    if (b == a) return true;
  return false;
}

// y of body b in the root's frame
double LateralY(const mjData* d, int root, int b) {
  const mjtNum* R = d->xmat + 9 * root;
  const mjtNum dx = d->xpos[3 * b] - d->xpos[3 * root], dy = d->xpos[3 * b + 1] - d->xpos[3 * root + 1],
               dz = d->xpos[3 * b + 2] - d->xpos[3 * root + 2];
  return R[1] * dx + R[4] * dy + R[7] * dz;  // (R^T d).y
}

// the hinge and slide joints from the root (excluded) down to body b, root first
std::vector<std::string> Leg(const mjModel* m, int root, int b) {
  std::vector<std::string> joints;
  for (; b > 0 && b != root; b = m->body_parentid[b])
    for (int k = m->body_jntnum[b] - 1; k >= 0; --k) {
      const int j = m->body_jntadr[b] + k;
      if (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE)
        joints.insert(joints.begin(), Name(m, mjOBJ_JOINT, j));
    }
  return joints;
}

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};

}  // namespace

bool DraftProfile(const std::string& model_path, const std::string& profile_path,
                  std::string* yaml, std::string* error) {
  if (IsProfilePath(model_path)) {
    *error = "'" + model_path + "' is a profile already: --init takes the robot's model";
    return false;
  }
  ModelPtr m(LoadMujocoModel(model_path, error));
  if (!m) return false;
  std::unique_ptr<mjData, DataDeleter> d(mj_makeData(m.get()));
  std::vector<std::string> missing;
  std::string out;
  auto line = [&out](const std::string& s) { out += s + "\n"; };

  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path dir = fs::absolute(fs::path(profile_path)).parent_path();
  const std::string rel = fs::relative(fs::absolute(model_path), dir, ec).string();
  line("# Robot profile drafted by `ohrp profile --init " + model_path + "`: review every value");
  line("# (docs/robots.md, \"Robot profiles\", says what each key does).");
  line("model: " + (ec || rel.empty() ? fs::absolute(model_path).string() : rel));

  // the reference configuration: a keyframe, else qpos0
  int key = mj_name2id(m.get(), mjOBJ_KEY, "stand");
  if (key < 0 && m->nkey > 0) key = 0;
  if (key >= 0) mju_copy(d->qpos, m->key_qpos + key * m->nq, m->nq);
  mj_kinematics(m.get(), d.get());
  const std::string config = key >= 0 ? "keyframe '" + Name(m.get(), mjOBJ_KEY, key) + "'" : "qpos0";

  const int root = profile::RootBody(m.get());
  bool floating = false;
  for (int j = 0; j < m->njnt; ++j) floating = floating || m->jnt_type[j] == mjJNT_FREE;
  if (!floating) missing.push_back("a floating base: a free joint on the robot's root body");
  if (m->nu == 0)
    missing.push_back("actuators: the model has none (a <motor> or <position> per joint; a URDF "
                      "needs them added in MJCF)");

  // feet: the lowest body, then the lowest body on the other side of the root that is neither
  // its ancestor nor its descendant
  int foot[2] = {-1, -1};
  double low[2] = {INFINITY, INFINITY};
  for (int b = 1; root >= 0 && b < m->nbody; ++b) {
    if (b == root || !IsAncestor(m.get(), root, b)) continue;
    const double z = profile::LowestZ(m.get(), d.get(), b);
    if (z < low[0]) low[0] = z, foot[0] = b;
  }
  for (int b = 1; foot[0] >= 0 && b < m->nbody; ++b) {
    if (b == root || !IsAncestor(m.get(), root, b) || IsAncestor(m.get(), b, foot[0]) ||
        IsAncestor(m.get(), foot[0], b))
      continue;
    if (LateralY(d.get(), root, b) * LateralY(d.get(), root, foot[0]) >= 0) continue;
    const double z = profile::LowestZ(m.get(), d.get(), b);
    if (z < low[1]) low[1] = z, foot[1] = b;
  }
  if (foot[1] < 0) {
    missing.push_back("two feet: the lowest bodies of two legs on either side of the root (found " +
                      std::string(foot[0] < 0 ? "none" : "only '" + Name(m.get(), mjOBJ_BODY, foot[0]) + "'") +
                      "); write feet.left.body and feet.right.body");
  } else {
    if (LateralY(d.get(), root, foot[0]) < LateralY(d.get(), root, foot[1])) std::swap(foot[0], foot[1]);
    line("# the feet: the lowest bodies (their lowest geoms at " + config + ") of the two legs; left");
    line("# is the one at larger y in the root body's frame");
    line("feet:");
    for (int s = 0; s < 2; ++s) {
      const char* side = s == 0 ? "left" : "right";
      const std::string body = Name(m.get(), mjOBJ_BODY, foot[s]);
      if (body.empty()) missing.push_back(std::string(side) + " foot: body #" + std::to_string(foot[s]) + " has no name");
      line(std::string("  ") + side + ":");
      line("    body: " + body);
      if (const int g = profile::SoleGeom(m.get(), foot[s]); g >= 0) {
        line("    # its sole: the model's own box " + Name(m.get(), mjOBJ_GEOM, g));
        continue;
      }
      std::array<double, 2> size{};
      std::array<double, 3> centre{};
      std::string how;
      if (!profile::DeriveSole(m.get(), foot[s], &size, &centre, &how)) {
        missing.push_back(std::string("feet.") + side + ".sole: " + how + "; write size and centre");
        continue;
      }
      line("    # from " + how);
      line("    sole: {size: [" + Num(size[0]) + ", " + Num(size[1]) + "], centre: [" +
           Num(centre[0]) + ", " + Num(centre[1]) + ", " + Num(centre[2]) + "]}");
    }
    line("# soft: the soles replace the feet's own colliding geoms; native: the author's geoms stay");
    line("contact: soft");
  }

  // sensors
  bool ft[2] = {false, false};
  for (int s = 0; s < 2; ++s) ft[s] = foot[s] >= 0 && profile::HasForceTorque(m.get(), foot[s]);
  line(std::string("# ") + (ft[0] && ft[1] ? "the model has a <force> + <torque> site above each foot"
                                          : "auto: a <force> + <torque> site at a foot body's origin where the model has none"));
  line("force_torque: auto");
  const int imu = profile::ImuSite(m.get());
  line(imu >= 0 ? "# the model's IMU: site '" + Name(m.get(), mjOBJ_SITE, imu) + "' (gyro + accelerometer)"
                : "# auto: a gyro + accelerometer site at the root body '" + Name(m.get(), mjOBJ_BODY, root) + "'s origin");
  line("imu: auto");

  // stance
  if (key >= 0) {
    line("# the stance: the model's keyframe (the applications use the keyframe 'stand')");
    line("stand: {keyframe: " + Name(m.get(), mjOBJ_KEY, key) + "}");
  } else {
    line("# the stance: no keyframe in the model; qpos0's joint values, the base height derived");
    line("# so that the soles touch z = 0. Bend the knees here.");
    line("stand:");
    line("  joints:");
    for (int j = 0; j < m->njnt; ++j)
      if (m->jnt_type[j] == mjJNT_HINGE || m->jnt_type[j] == mjJNT_SLIDE)
        line("    " + Name(m.get(), mjOBJ_JOINT, j) + ": " + Num(m->qpos0[m->jnt_qposadr[j]]));
  }
  if (foot[1] >= 0) {
    line("# the legs: the joints from the root body to each foot (listed for the applications)");
    line("chains:");
    for (int s = 0; s < 2; ++s) {
      std::string list;
      for (const std::string& j : Leg(m.get(), root, foot[s])) list += (list.empty() ? "" : ", ") + j;
      line(std::string("  ") + (s == 0 ? "left_leg" : "right_leg") + ": [" + list + "]");
    }
  }
  if (!missing.empty()) {
    *error = "cannot draft a profile for '" + model_path + "': " + std::to_string(missing.size()) +
             " requirement" + (missing.size() > 1 ? "s" : "") + " not derivable (all listed):";
    for (const std::string& s : missing) *error += "\n  - " + s;
    return false;
  }
  *yaml = out;
  return true;
}

}  // namespace ohrp::model
