// The static obstacles of a MuJoCo scene (issue 34 item 3): the geoms a planner keeps clear of,
// read with the project's one model loader (load.h) from the same MJCF file sim_host simulates.
//
// Static: a geom of a body welded to the world (the world body itself, or bodies with no joint
// between them and it: mjModel::body_weldid is 0). The robot's links hang under its free joint
// and are never static. Left out: planes (the floor), height fields and meshes (not boxes; named
// in `skipped`). Boxes are kept as they are; spheres, capsules, cylinders and ellipsoids become
// their bounding boxes in the geom's frame (a conservative box: the planner keeps clear of more
// than the shape). Poses are in the scene's world frame; BoxInFrame places one in another frame
// (a robot's base frame, from the base pose it has when it plans).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace ohrp::model {

struct SceneObstacle {
  std::string name;   // the geom's name, or "geom<id>" when it has none
  std::string shape;  // "box", "sphere", "capsule", "cylinder", "ellipsoid" (the MJCF type)
  Eigen::Vector3d half_size = Eigen::Vector3d::Zero();         // of the (bounding) box [m]
  Eigen::Isometry3d X_WO = Eigen::Isometry3d::Identity();      // its pose in the world
};

struct SceneObstacles {
  std::vector<SceneObstacle> boxes;
  std::vector<std::string> skipped;  // static geoms not taken (meshes, height fields), by name
};

// Reads `path` (MJCF, loaded and compiled by MuJoCo). False with `*error` naming the file when it
// does not load or has no static obstacle (a planner given an empty scene would be told nothing).
bool ReadSceneObstacles(const std::string& path, SceneObstacles* out, std::string* error);

// The box's pose in frame B when B is at `X_WB` in the world: X_BO = X_WB^-1 X_WO.
inline Eigen::Isometry3d BoxInFrame(const SceneObstacle& box, const Eigen::Isometry3d& X_WB) {
  return X_WB.inverse() * box.X_WO;
}

}  // namespace ohrp::model
