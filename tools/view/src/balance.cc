// The balance overlays' data: the robot's centre of mass and each sole sensor's measured force,
// centre of pressure and sole corners in the world (geometry.h, SceneGeometry::Balance).
#include <cmath>

#include "view/geometry.h"

namespace ohrp::view {

namespace {

// the robot's root body (the body of its first joint's tree under the world)
int RootBody(const mjModel* m, const model::RobotMap& robot) {
  if (!robot.joints.empty()) {
    for (int j = 0; j < m->njnt; ++j)
      if (m->jnt_qposadr[j] == robot.joints[0].qpos_adr) return m->body_rootid[m->jnt_bodyid[j]];
  }
  return m->nbody > 1 ? m->body_rootid[1] : 0;
}

// a box geom's bottom face (its -z face in its own frame) in the world: four corners, in order
// around the face
nlohmann::json BottomCorners(const mjModel* m, const mjData* d, int g) {
  nlohmann::json out = nlohmann::json::array();
  if (g < 0 || m->geom_type[g] != mjGEOM_BOX) return out;
  const double* s = m->geom_size + 3 * g;
  const double* R = d->geom_xmat + 9 * g;
  const double* p = d->geom_xpos + 3 * g;
  const double sx[4] = {1, 1, -1, -1}, sy[4] = {1, -1, -1, 1};
  for (int k = 0; k < 4; ++k) {
    const double local[3] = {sx[k] * s[0], sy[k] * s[1], -s[2]};
    double w[3];
    mju_mulMatVec(w, R, local, 3, 3);
    out.push_back({p[0] + w[0], p[1] + w[1], p[2] + w[2]});
  }
  return out;
}

}  // namespace

nlohmann::json SceneGeometry::Balance(const RobotState& state, double min_foot_fz) {
  const mjModel* m = scene_->m();
  mjData* d = scene_->d();
  mj_comPos(m, d);  // subtree_com from the poses of the last mj_kinematics
  const int root = RootBody(m, robot_);
  nlohmann::json out;
  out["com"] = {d->subtree_com[3 * root], d->subtree_com[3 * root + 1], d->subtree_com[3 * root + 2]};
  out["feet"] = nlohmann::json::array();
  const size_t n = std::min(state.ft.size(), robot_.forces.size());
  for (size_t i = 0; i < n; ++i) {
    if (!sole_sensor_[i]) continue;
    const int s = robot_.forces[i].site_id;
    const double* R = d->site_xmat + 9 * s;
    const double* p = d->site_xpos + 3 * s;
    double f[3], t[3];
    mju_mulMatVec(f, R, state.ft[i].force, 3, 3);
    mju_mulMatVec(t, R, state.ft[i].torque, 3, 3);
    // the centre of pressure c on the plane z = p_z through the sensor: the moment about c,
    // t + (p - c) x f, has no horizontal part
    const bool loaded = f[2] >= min_foot_fz;
    double c[3] = {p[0], p[1], p[2]};
    if (loaded) {
      c[0] = p[0] - t[1] / f[2];
      c[1] = p[1] + t[0] / f[2];
    }
    out["feet"].push_back({{"sensor", robot_.forces[i].name},
                           {"loaded", loaded},
                           {"f", {f[0], f[1], f[2]}},
                           {"cop", {c[0], c[1], c[2]}},
                           {"corners", BottomCorners(m, d, sole_geom_[i])}});
  }
  return out;
}

std::array<double, 3> SceneGeometry::BoxBottom(int g) const {
  const mjModel* m = scene_->m();
  const mjData* d = scene_->d();
  const double* R = d->geom_xmat + 9 * g;
  const double h = m->geom_size[3 * g + 2];
  return {d->geom_xpos[3 * g] - R[2] * h, d->geom_xpos[3 * g + 1] - R[5] * h, d->geom_xpos[3 * g + 2] - R[8] * h};
}

std::array<double, 3> SceneGeometry::BodyOrigin(int b) const {
  const mjData* d = scene_->d();
  return {d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]};
}

}  // namespace ohrp::view
