// What a robot profile derives from a compiled model (see derive.h).
#include "profile/derive.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace ohrp::model::profile {
namespace {

struct Point {
  double x, y, z;
};

// p_body = pos + R(quat) p_geom
Point ToBody(const mjtNum* pos, const mjtNum* quat, const mjtNum local[3]) {
  mjtNum out[3];
  mju_rotVecQuat(out, local, quat);
  return {pos[0] + out[0], pos[1] + out[1], pos[2] + out[2]};
}

// the geom's candidate lowest points in the body frame
void GeomPoints(const mjModel* m, int g, std::vector<Point>* pts) {
  const mjtNum* pos = m->geom_pos + 3 * g;
  const mjtNum* quat = m->geom_quat + 4 * g;
  const mjtNum* s = m->geom_size + 3 * g;
  auto add = [&](double x, double y, double z, double drop) {
    const mjtNum local[3] = {x, y, z};
    Point p = ToBody(pos, quat, local);
    p.z -= drop;
    pts->push_back(p);
  };
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE: add(0, 0, 0, s[0]); break;
    case mjGEOM_CAPSULE: add(0, 0, -s[1], s[0]); add(0, 0, s[1], s[0]); break;
    case mjGEOM_CYLINDER:
      for (int k = 0; k < 16; ++k) {
        const double a = 2 * M_PI * k / 16;
        add(s[0] * std::cos(a), s[0] * std::sin(a), -s[1], 0);
        add(s[0] * std::cos(a), s[0] * std::sin(a), s[1], 0);
      }
      break;
    case mjGEOM_BOX:
    case mjGEOM_ELLIPSOID:  // its bounding box
      for (int k = 0; k < 8; ++k)
        add((k & 1 ? 1 : -1) * s[0], (k & 2 ? 1 : -1) * s[1], (k & 4 ? 1 : -1) * s[2], 0);
      break;
    case mjGEOM_MESH: {
      const int mesh = m->geom_dataid[g];
      if (mesh < 0) break;
      const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
      for (int k = 0; k < m->mesh_vertnum[mesh]; ++k) add(v[3 * k], v[3 * k + 1], v[3 * k + 2], 0);
      break;
    }
    default: break;  // planes and height fields: not a foot
  }
}

// the body's contact candidates: its colliding geoms, or all when none collides
std::vector<Point> BodyPoints(const mjModel* m, int b, int* used, bool* any_collides) {
  *any_collides = false;
  *used = 0;
  const int first = m->body_geomadr[b], n = first < 0 ? 0 : m->body_geomnum[b];
  for (int g = first; g < first + n; ++g) *any_collides = *any_collides || Collides(m, g);
  std::vector<Point> pts;
  for (int g = first; g < first + n; ++g) {
    if (*any_collides && !Collides(m, g)) continue;
    GeomPoints(m, g, &pts);
    ++*used;
  }
  return pts;
}

}  // namespace

double LowestZ(const mjModel* m, const mjData* d, int b) {
  int used = 0;
  bool collides = false;
  double low = INFINITY;
  for (const Point& p : BodyPoints(m, b, &used, &collides)) {
    const mjtNum* R = d->xmat + 9 * b;
    low = std::min(low, d->xpos[3 * b + 2] + R[6] * p.x + R[7] * p.y + R[8] * p.z);
  }
  return low;
}

bool DeriveSole(const mjModel* m, int b, std::array<double, 2>* size,
                std::array<double, 3>* centre, std::string* how) {
  int used = 0;
  bool any_collides = false;
  const std::vector<Point> pts = BodyPoints(m, b, &used, &any_collides);
  if (pts.empty()) {
    *how = "the body has no geom to take a sole from";
    return false;
  }
  double low = INFINITY;
  for (const Point& p : pts) low = std::min(low, p.z);
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Point& p : pts) {
    if (p.z > low + kLowestTolerance) continue;
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  *size = {x1 - x0, y1 - y0};
  *centre = {0.5 * (x0 + x1), 0.5 * (y0 + y1), low};
  *how = "the lowest points (within " + std::to_string(static_cast<int>(kLowestTolerance * 1000)) +
         " mm) of the body's " + std::to_string(used) + (any_collides ? " colliding" : "") +
         " geoms, in its frame";
  if ((*size)[0] < 1e-3 || (*size)[1] < 1e-3) {
    *how += ": a line or a point, not a rectangle";
    return false;
  }
  return true;
}

int SoleGeom(const mjModel* m, int b) {
  for (int g = m->body_geomadr[b]; g >= 0 && g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    const size_t n = name ? std::strlen(name) : 0;
    if (m->geom_type[g] == mjGEOM_BOX && n > 5 && std::strcmp(name + n - 5, "_SOLE") == 0) return g;
  }
  return -1;
}

int RootBody(const mjModel* m) {
  for (int j = 0; j < m->njnt; ++j)
    if (m->jnt_type[j] == mjJNT_FREE) return m->jnt_bodyid[j];
  return m->nbody > 1 ? 1 : -1;
}

namespace {
bool SensorOnSite(const mjModel* m, int type, int site) {
  for (int s = 0; s < m->nsensor; ++s)
    if (m->sensor_type[s] == type && m->sensor_objtype[s] == mjOBJ_SITE && m->sensor_objid[s] == site)
      return true;
  return false;
}
}  // namespace

bool HasForceTorque(const mjModel* m, int b) {
  for (; b > 0; b = m->body_parentid[b]) {
    for (int site = 0; site < m->nsite; ++site) {
      if (m->site_bodyid[site] == b && SensorOnSite(m, mjSENS_FORCE, site) &&
          SensorOnSite(m, mjSENS_TORQUE, site))
        return true;
    }
  }
  return false;
}

int ImuSite(const mjModel* m) {
  for (int site = 0; site < m->nsite; ++site)
    if (SensorOnSite(m, mjSENS_GYRO, site) && SensorOnSite(m, mjSENS_ACCELEROMETER, site)) return site;
  return -1;
}

}  // namespace ohrp::model::profile
