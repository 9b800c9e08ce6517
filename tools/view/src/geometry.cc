// The scene's geoms for the page, and their world poses by forward kinematics (geometry.h).
#include "view/geometry.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

namespace ohrp::view {

namespace {

// geoms of these groups are drawn (MuJoCo's viewer shows 0-2 by default)
constexpr int kVisibleGroups = 3;

const char* TypeName(int type) {
  switch (type) {
    case mjGEOM_PLANE: return "plane";
    case mjGEOM_SPHERE: return "sphere";
    case mjGEOM_CAPSULE: return "capsule";
    case mjGEOM_ELLIPSOID: return "ellipsoid";
    case mjGEOM_CYLINDER: return "cylinder";
    case mjGEOM_BOX: return "box";
    case mjGEOM_MESH: return "mesh";
    case mjGEOM_HFIELD: return "hfield";
    default: return nullptr;
  }
}

// the position of MuJoCo id `id` in `ids` (the description's "meshes" or "hfields"), added at
// the end when it is not there yet: each asset is sent once however many geoms draw it
int Slot(std::vector<int>* ids, int id) {
  const auto at = std::find(ids->begin(), ids->end(), id);
  if (at != ids->end()) return static_cast<int>(at - ids->begin());
  ids->push_back(id);
  return static_cast<int>(ids->size()) - 1;
}

}  // namespace

std::unique_ptr<SceneGeometry> SceneGeometry::Load(const std::string& path, std::string* error) {
  std::unique_ptr<SceneGeometry> g(new SceneGeometry());
  g->scene_ = model::Scene::Load(path, error);
  if (!g->scene_) return nullptr;
  if (!model::MapRobot(g->scene_->m(), &g->robot_, error)) {
    *error = path + ": " + *error;
    return nullptr;
  }
  // static geoms belong to the world body; every other visible geom moves with the robot
  const mjModel* m = g->scene_->m();
  for (int i = 0; i < m->ngeom; ++i) {
    if (!TypeName(m->geom_type[i]) || m->geom_group[i] < 0 || m->geom_group[i] >= kVisibleGroups)
      continue;
    const float* rgba = m->geom_matid[i] >= 0 ? m->mat_rgba + 4 * m->geom_matid[i] : m->geom_rgba + 4 * i;
    if (rgba[3] <= 0) continue;
    (m->geom_bodyid[i] == 0 ? g->static_geoms_ : g->moving_geoms_).push_back(i);
    // a mesh or a height field is sent once, however many geoms draw it
    if (m->geom_type[i] == mjGEOM_MESH) g->geom_asset_[i] = Slot(&g->meshes_, m->geom_dataid[i]);
    if (m->geom_type[i] == mjGEOM_HFIELD) g->geom_asset_[i] = Slot(&g->hfields_, m->geom_dataid[i]);
  }
  // the sole sensors: a sensor's body is a *_SOLE geom's body or one of its ancestors
  for (const auto& f : g->robot_.forces) {
    const int body = m->site_bodyid[f.site_id];
    int sole = -1;
    for (int i = 0; i < m->ngeom && sole < 0; ++i) {
      const char* name = mj_id2name(m, mjOBJ_GEOM, i);
      const std::string n = name ? name : "";
      if (n.size() < 5 || n.compare(n.size() - 5, 5, "_SOLE") != 0) continue;
      for (int b = m->geom_bodyid[i]; b > 0 && sole < 0; b = m->body_parentid[b]) sole = b == body ? i : -1;
    }
    g->sole_sensor_.push_back(sole >= 0);
    g->sole_geom_.push_back(sole);
  }
  if (std::find(g->sole_sensor_.begin(), g->sole_sensor_.end(), true) == g->sole_sensor_.end())
    g->sole_sensor_.assign(g->sole_sensor_.size(), true);
  mj_kinematics(m, g->scene_->d());
  g->description_ = g->MakeDescription();
  return g;
}

nlohmann::json SceneGeometry::Geom(int g) const {
  const mjModel* m = scene_->m();
  const float* rgba = m->geom_matid[g] >= 0 ? m->mat_rgba + 4 * m->geom_matid[g] : m->geom_rgba + 4 * g;
  nlohmann::json j;
  j["type"] = TypeName(m->geom_type[g]);
  j["size"] = {m->geom_size[3 * g], m->geom_size[3 * g + 1], m->geom_size[3 * g + 2]};
  j["rgba"] = {rgba[0], rgba[1], rgba[2], rgba[3]};
  const char* name = mj_id2name(m, mjOBJ_GEOM, g);
  j["name"] = name ? name : "";
  const char* body = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
  j["body"] = body ? body : "";  // the page's push picks a body by its geoms
  if (m->geom_type[g] == mjGEOM_MESH) j["mesh"] = geom_asset_.at(g);
  if (m->geom_type[g] == mjGEOM_HFIELD) j["hfield"] = geom_asset_.at(g);
  return j;
}

std::string Base64(const void* data, size_t bytes) {
  static const char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  for (size_t i = 0; i < bytes; i += 3) {
    const size_t n = std::min<size_t>(3, bytes - i);
    const uint32_t w = (uint32_t{p[i]} << 16) | (n > 1 ? uint32_t{p[i + 1]} << 8 : 0) |
                       (n > 2 ? uint32_t{p[i + 2]} : 0);
    out += kDigits[(w >> 18) & 63];
    out += kDigits[(w >> 12) & 63];
    out += n > 1 ? kDigits[(w >> 6) & 63] : '=';
    out += n > 2 ? kDigits[w & 63] : '=';
  }
  return out;
}

MeshData CompactMesh(const mjModel* m, int mesh) {
  const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  const int* f = m->mesh_face + 3 * m->mesh_faceadr[mesh];
  MeshData out;
  std::map<std::array<float, 3>, uint32_t> index;  // a position's index in out.vertices
  std::vector<uint32_t> remap(m->mesh_vertnum[mesh]);
  for (int k = 0; k < m->mesh_vertnum[mesh]; ++k) {
    const std::array<float, 3> p{v[3 * k], v[3 * k + 1], v[3 * k + 2]};
    const auto [it, added] = index.emplace(p, static_cast<uint32_t>(out.vertices.size() / 3));
    if (added) out.vertices.insert(out.vertices.end(), p.begin(), p.end());
    remap[k] = it->second;
  }
  out.faces.reserve(3 * m->mesh_facenum[mesh]);
  for (int k = 0; k < 3 * m->mesh_facenum[mesh]; ++k) out.faces.push_back(remap[f[k]]);
  return out;
}

nlohmann::json SceneGeometry::Mesh(int mesh) const {
  // MuJoCo's compiled mesh, in the frame its geoms' poses place (centred and aligned by the
  // compiler), its repeated positions merged (an STL repeats each corner in every triangle);
  // binary in base64 for size: H1's 143k vertices and 286k triangles are 6.9 MB so, 13.2 MB
  // as JSON numbers
  const MeshData d = CompactMesh(scene_->m(), mesh);
  nlohmann::json j;
  const char* name = mj_id2name(scene_->m(), mjOBJ_MESH, mesh);
  j["name"] = name ? name : "";
  j["nvert"] = d.vertices.size() / 3;
  j["nface"] = d.faces.size() / 3;
  j["vertices"] = Base64(d.vertices.data(), d.vertices.size() * sizeof(float));
  j["faces"] = Base64(d.faces.data(), d.faces.size() * sizeof(uint32_t));
  return j;
}

std::vector<float> HfieldHeights(const mjModel* m, int hfield) {
  const int n = m->hfield_nrow[hfield] * m->hfield_ncol[hfield];
  const float* data = m->hfield_data + m->hfield_adr[hfield];
  const double top = m->hfield_size[4 * hfield + 2];
  std::vector<float> out(n);
  for (int i = 0; i < n; ++i) out[i] = static_cast<float>(top * data[i]);
  return out;
}

nlohmann::json SceneGeometry::Hfield(int hfield) const {
  const mjModel* m = scene_->m();
  const std::vector<float> heights = HfieldHeights(m, hfield);
  nlohmann::json j;
  const char* name = mj_id2name(m, mjOBJ_HFIELD, hfield);
  j["name"] = name ? name : "";
  j["nrow"] = m->hfield_nrow[hfield];
  j["ncol"] = m->hfield_ncol[hfield];
  j["size"] = {m->hfield_size[4 * hfield], m->hfield_size[4 * hfield + 1],
               m->hfield_size[4 * hfield + 2], m->hfield_size[4 * hfield + 3]};
  j["heights"] = Base64(heights.data(), heights.size() * sizeof(float));
  return j;
}

nlohmann::json SceneGeometry::MakeDescription() const {
  const mjData* d = scene_->d();
  nlohmann::json out;
  out["robot"] = robot_.name;
  // static geoms with their (fixed) world pose
  out["static"] = nlohmann::json::array();
  for (int g : static_geoms_) {
    nlohmann::json j = Geom(g);
    double quat[4];
    mju_mat2Quat(quat, d->geom_xmat + 9 * g);
    j["pose"] = {d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2],
                 quat[0], quat[1], quat[2], quat[3]};
    out["static"].push_back(j);
  }
  out["moving"] = nlohmann::json::array();
  for (int g : moving_geoms_) out["moving"].push_back(Geom(g));
  out["meshes"] = nlohmann::json::array();
  for (int mesh : meshes_) out["meshes"].push_back(Mesh(mesh));
  out["hfields"] = nlohmann::json::array();
  for (int h : hfields_) out["hfields"].push_back(Hfield(h));
  out["joints"] = nlohmann::json::array();
  for (const auto& jm : robot_.joints) out["joints"].push_back(jm.name);
  out["forces"] = nlohmann::json::array();
  for (const auto& f : robot_.forces) out["forces"].push_back(f.name);
  // the sensors the ZMP and the balance overlays use (Balance)
  out["soles"] = nlohmann::json::array();
  for (size_t i = 0; i < robot_.forces.size(); ++i)
    if (sole_sensor_[i]) out["soles"].push_back(robot_.forces[i].name);
  return out;
}

nlohmann::json SceneGeometry::Poses(const RobotState& state) {
  const mjModel* m = scene_->m();
  mjData* d = scene_->d();
  // base pose and joints into qpos, then the kinematics
  if (robot_.base_qpos >= 0) {
    for (int k = 0; k < 3; ++k) d->qpos[robot_.base_qpos + k] = state.p_WB[k];
    for (int k = 0; k < 4; ++k) d->qpos[robot_.base_qpos + 3 + k] = state.quat_WB[k];
    mju_normalize4(d->qpos + robot_.base_qpos + 3);
  }
  const size_t n = std::min(state.q.size(), robot_.joints.size());
  for (size_t i = 0; i < n; ++i)
    if (std::isfinite(state.q[i])) d->qpos[robot_.joints[i].qpos_adr] = state.q[i];
  mj_kinematics(m, d);
  // one pose per moving geom
  nlohmann::json poses = nlohmann::json::array();
  for (int g : moving_geoms_) {
    double quat[4];
    mju_mat2Quat(quat, d->geom_xmat + 9 * g);
    poses.push_back({d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2],
                     quat[0], quat[1], quat[2], quat[3]});
  }
  return poses;
}

bool SceneGeometry::Zmp(const RobotState& state, double zmp[2], double min_fz) const {
  const mjData* d = scene_->d();
  // each sensor's wrench in the world, its moment taken about the world origin at z = 0:
  // the ZMP (x, y) is where the total moment's horizontal part vanishes
  double fz = 0, mx = 0, my = 0;
  const size_t n = std::min(state.ft.size(), robot_.forces.size());
  for (size_t i = 0; i < n; ++i) {
    if (!sole_sensor_[i]) continue;
    const int s = robot_.forces[i].site_id;
    const double* R = d->site_xmat + 9 * s;  // sensor frame in world (row-major)
    const double* p = d->site_xpos + 3 * s;
    double f[3], t[3];
    mju_mulMatVec(f, R, state.ft[i].force, 3, 3);
    mju_mulMatVec(t, R, state.ft[i].torque, 3, 3);
    // moment about the origin: t + p x f
    mx += t[0] + p[1] * f[2] - p[2] * f[1];
    my += t[1] + p[2] * f[0] - p[0] * f[2];
    fz += f[2];
  }
  if (fz < min_fz) return false;
  zmp[0] = -my / fz;
  zmp[1] = mx / fz;
  return true;
}

}  // namespace ohrp::view
