// The static obstacles of a MuJoCo scene (scene_obstacles.h).
#include "robot_model/scene_obstacles.h"

#include <mujoco/mujoco.h>

#include "robot_model/load.h"

namespace ohrp::model {
namespace {

std::string GeomName(const mjModel* m, int g) {
  const char* n = mj_id2name(m, mjOBJ_GEOM, g);
  return n && *n ? std::string(n) : "geom" + std::to_string(g);
}

// the half sizes of geom g's bounding box in its own frame; false for shapes that have none here
bool HalfSize(const mjModel* m, int g, Eigen::Vector3d* h, std::string* shape) {
  const double* s = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_BOX: *shape = "box"; *h = {s[0], s[1], s[2]}; return true;
    case mjGEOM_SPHERE: *shape = "sphere"; *h = {s[0], s[0], s[0]}; return true;
    case mjGEOM_CAPSULE: *shape = "capsule"; *h = {s[0], s[0], s[1] + s[0]}; return true;
    case mjGEOM_CYLINDER: *shape = "cylinder"; *h = {s[0], s[0], s[1]}; return true;
    case mjGEOM_ELLIPSOID: *shape = "ellipsoid"; *h = {s[0], s[1], s[2]}; return true;
    default: return false;
  }
}

}  // namespace

bool ReadSceneObstacles(const std::string& path, SceneObstacles* out, std::string* error) {
  *out = SceneObstacles();
  std::string why;
  ModelPtr m(LoadMujocoModel(path, &why));
  if (!m) {
    *error = "--scene: " + why;
    return false;
  }
  mjData* d = mj_makeData(m.get());
  mj_kinematics(m.get(), d);  // the world poses of the static geoms (qpos0: they do not move)
  for (int g = 0; g < m->ngeom; ++g) {
    const int body = m->geom_bodyid[g];
    if (m->body_weldid[body] != 0) continue;  // moves: the robot, a free object
    const int type = m->geom_type[g];
    if (type == mjGEOM_PLANE) continue;       // the floor
    SceneObstacle o;
    o.name = GeomName(m.get(), g);
    if (!HalfSize(m.get(), g, &o.half_size, &o.shape)) {
      out->skipped.push_back(o.name);
      continue;
    }
    Eigen::Matrix3d R;
    for (int i = 0; i < 9; ++i) R(i / 3, i % 3) = d->geom_xmat[9 * g + i];  // row-major
    o.X_WO.linear() = R;
    o.X_WO.translation() = Eigen::Vector3d(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]);
    out->boxes.push_back(o);
  }
  mj_deleteData(d);
  if (out->boxes.empty()) {
    *error = "--scene: " + path + " has no static obstacle (boxes, spheres, capsules, cylinders "
             "or ellipsoids fixed to the world; the floor plane does not count)";
    return false;
  }
  return true;
}

}  // namespace ohrp::model
