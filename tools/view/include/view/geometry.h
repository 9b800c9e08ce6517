// The viewer's picture of a scene: the geoms of the MJCF (shape, size, colour), split into the
// static ones (the world body's: floor, steps) sent once, and the moving ones (the robot's),
// whose world poses are computed here by forward kinematics (mj_kinematics) from the base pose
// and the joint angles of a sensor block or a log row. The page only places boxes and cylinders
// where it is told (and draws the meshes and height fields the description carries): the
// geometry is exact and the page needs no kinematic tree.
//
// Units: SI (m, rad); poses are (x, y, z, qw, qx, qy, qz) in the world frame.
#pragma once

#include <mujoco/mujoco.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "robot_model/model.h"
#include "shm_bridge/layout.h"

namespace ohrp::view {

// One robot state: what the forward kinematics needs, plus the ankle wrenches for the ZMP.
struct RobotState {
  double p_WB[3] = {0, 0, 0};         // base position [m]
  double quat_WB[4] = {1, 0, 0, 0};   // base orientation (w, x, y, z)
  std::vector<double> q;              // joint positions, segment joint-id order [rad or m]
  std::vector<shm::ForceTorque> ft;   // force/torque sensors, segment order (may be empty)
};

// A mesh for the page: MuJoCo's compiled vertices, in the frame its geoms' poses place, with
// repeated positions merged, and its triangles as indices into them.
struct MeshData {
  std::vector<float> vertices;   // x, y, z, ... [m]
  std::vector<uint32_t> faces;   // i, j, k, ...
};
MeshData CompactMesh(const mjModel* m, int mesh);

// A height field's elevations [m] for the page: MuJoCo's samples (hfield_data, 0..1) times its
// top height, row-major, row r at y = -size_y + 2 size_y r / (nrow - 1), column c at
// x = -size_x + 2 size_x c / (ncol - 1) in its geom's frame (as MuJoCo draws and collides it).
std::vector<float> HfieldHeights(const mjModel* m, int hfield);

// `bytes` bytes at `data` in base64 (RFC 4648, with padding).
std::string Base64(const void* data, size_t bytes);

class SceneGeometry {
 public:
  // Loads the MJCF scene at `path` and maps its robot. Returns null with `*error` naming the
  // file and MuJoCo's message, or what the robot map refused.
  static std::unique_ptr<SceneGeometry> Load(const std::string& path, std::string* error);

  // The scene's description for the page: {"static": [geom...], "moving": [geom...],
  // "joints": [names], "forces": [names], "soles": [the force sensors under soles], "robot": name, "meshes": [mesh...],
  // "hfields": [height field...]}; each geom is {"type", "size", "rgba"}, for static ones
  // "pose", for a mesh geom "mesh" (its index in "meshes"); each mesh is {"name", "nvert",
  // "nface", "vertices", "faces"}, CompactMesh's arrays as base64 (little-endian float32 x, y,
  // z [m]; uint32 i, j, k), sent once however many geoms draw it. Likewise a height field
  // geom's "hfield" indexes "hfields", each {"name", "nrow", "ncol", "size" (MuJoCo's four),
  // "heights"} (HfieldHeights as float32 in base64). Only visible geoms (group 0-2, alpha > 0).
  // Made once at Load: safe to call from any thread while another calls Poses().
  const nlohmann::json& Describe() const { return description_; }

  // World poses of the moving geoms for `state` (one 7-array per geom, order of Describe()).
  // Joints missing from `state.q` keep the model's initial position.
  nlohmann::json Poses(const RobotState& state);

  // The zero-moment point on the plane z = 0 from the sole sensors (the force/torque sensors
  // above a geom named *_SOLE, sim_host's convention; every sensor when none is) at the poses of
  // the last Poses() call: false when they carry less than `min_fz` [N] in total (in the air).
  bool Zmp(const RobotState& state, double zmp[2], double min_fz = 20.0) const;

  // The balance overlays' data at the poses of the last Poses() call (docs/view.md, "Balance in
  // 3D"): {"com": [x, y, z] (the robot's centre of mass [m]), "feet": [{"sensor", "loaded"
  // (fz >= `min_foot_fz` [N]), "f": [fx, fy, fz] (the measured force in the world [N]), "cop":
  // [x, y, z] (where the foot's wrench has no horizontal moment on the plane of its sensor, or
  // the sensor's position when unloaded [m]), "corners": [[x, y, z] x 4] (the sole box's bottom
  // face, [] without a *_SOLE box)}...]} for the sole sensors.
  nlohmann::json Balance(const RobotState& state, double min_foot_fz = 10.0);

  // The centre of box geom `g`'s bottom face (its -z face) in the world at the poses of the
  // last Poses() call [m] (the walk plan's registration onto the soles, plan.h).
  std::array<double, 3> BoxBottom(int g) const;
  // body `b`'s origin in the world at the poses of the last Poses() call [m]
  std::array<double, 3> BodyOrigin(int b) const;

  const mjModel* model() const { return scene_->m(); }
  const model::RobotMap& robot() const { return robot_; }

 private:
  SceneGeometry() = default;
  nlohmann::json Geom(int g) const;
  nlohmann::json Mesh(int mesh) const;
  nlohmann::json Hfield(int hfield) const;
  nlohmann::json MakeDescription() const;

  std::unique_ptr<model::Scene> scene_;
  model::RobotMap robot_;
  std::vector<int> static_geoms_, moving_geoms_;
  std::vector<int> meshes_;        // MuJoCo mesh ids of the drawn geoms, in "meshes" order
  std::vector<int> hfields_;       // MuJoCo height field ids, in "hfields" order
  std::map<int, int> geom_asset_;  // a drawn mesh or height field geom: its index in those
  std::vector<bool> sole_sensor_;  // per force sensor: used for the ZMP
  std::vector<int> sole_geom_;     // per force sensor: its *_SOLE geom, or -1
  nlohmann::json description_;
};

}  // namespace ohrp::view
