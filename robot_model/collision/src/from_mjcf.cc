// The robot's collision geometry from MuJoCo's compiled model.
#include "collision/from_mjcf.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "mesh_hull.h"
#include "outer_hull.h"
#include "robot_model/model_hash.h"

namespace ohrp::collision {
namespace {

Eigen::Vector3d Vec(const mjtNum* v) { return Eigen::Vector3d(v[0], v[1], v[2]); }
Eigen::Quaterniond Quat(const mjtNum* q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]); }

// a mesh geom as the convex hull of its vertices: MuJoCo's (its graph: numvert, numface,
// vert_edgeadr, vert_globalid, edge_localid, face_globalid: the hull's vertices among the mesh's
// and its triangles) where it made one, Qhull's where it did not (MuJoCo 2.2 makes one only for
// meshes a colliding geom uses); a hull of more than kExactHullVertices vertices then becomes its
// outer polytope within kMeshHullTolerance (outer_hull.h), when that has fewer
bool MeshHull(const mjModel* m, int mesh, Shape* s, std::string* error) {
  const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < m->mesh_vertnum[mesh]; ++i) points.emplace_back(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  std::vector<Eigen::Vector3d> hull;
  std::vector<int> faces;
  const int adr = m->mesh_graphadr[mesh];
  if (adr < 0) {
    if (!ConvexHull(points, &hull, &faces, error)) return false;
  } else {
    const int* g = m->mesh_graph + adr;
    const int numvert = g[0], numface = g[1];
    const int* globalid = g + 2 + numvert;
    const int* face = g + 2 + 2 * numvert + (numvert + 3 * numface);
    std::map<int, int> local;  // mesh vertex -> hull vertex
    for (int i = 0; i < numvert; ++i) {
      local[globalid[i]] = i;
      hull.push_back(points[globalid[i]]);
    }
    for (int f = 0; f < numface; ++f) {
      faces.push_back(3);
      for (int k = 0; k < 3; ++k) faces.push_back(local.at(face[3 * f + k]));
    }
  }
  OuterPolytope outer;
  std::string why;
  if (hull.size() > kExactHullVertices &&
      OuterPolytopeOf(hull, faces, kMeshHullTolerance, 256, &outer, &why) &&
      outer.excess <= kMeshHullTolerance && outer.vertices.size() < hull.size()) {
    hull = std::move(outer.vertices);
    faces = std::move(outer.faces);
  }
  s->vertices = std::move(hull);
  s->faces = std::move(faces);
  return true;
}

// geoms g and h are the same shape at the same place (a visual and a collision geom of one mesh,
// as menagerie's G1 has on every body): the link keeps one
bool SameGeom(const mjModel* m, int g, int h) {
  return m->geom_type[g] == m->geom_type[h] && m->geom_dataid[g] == m->geom_dataid[h] &&
         std::equal(m->geom_size + 3 * g, m->geom_size + 3 * g + 3, m->geom_size + 3 * h) &&
         std::equal(m->geom_pos + 3 * g, m->geom_pos + 3 * g + 3, m->geom_pos + 3 * h) &&
         std::equal(m->geom_quat + 4 * g, m->geom_quat + 4 * g + 4, m->geom_quat + 4 * h);
}

const char* Name(const mjModel* m, mjtObj type, int id) {
  const char* n = mj_id2name(m, type, id);
  return n ? n : "(unnamed)";
}

// the limits of joint `j` for the geometry [rad or m]: an unlimited hinge turns all the way
// round (every orientation is within [-pi, pi]); false with `*error` for a slide without a range
// (its travel bounds how far the links below it move)
bool Limits(const mjModel* m, int j, const std::string& name, double lo, double hi,
            RobotGeometry* out, std::string* error) {
  const bool unlimited = lo <= -model::kNoLimit || hi >= model::kNoLimit;
  if (m->jnt_type[j] == mjJNT_SLIDE) {
    if (unlimited) {
      *error = "joint '" + name +
               "' is a slide without a range: give it one (range=\"lo hi\" limited=\"true\")";
      return false;
    }
    out->q_min.push_back(lo);
    out->q_max.push_back(hi);
    return true;
  }
  out->q_min.push_back(lo <= -model::kNoLimit ? -M_PI : lo);
  out->q_max.push_back(hi >= model::kNoLimit ? M_PI : hi);
  return true;
}

// a joint's pose offset: MuJoCo turns (slides) a body by q - ref (qpos0), the geometry by q, so
// the body's pose in its parent becomes the one at q = 0: turned by -ref about the hinge's axis
// through its anchor (which that turn leaves in place), or slid by -ref along the slide's axis
void RebaseToZero(const mjModel* m, int j, Link* l) {
  const double ref = m->qpos0[m->jnt_qposadr[j]];
  if (ref == 0) return;
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translate(l->p_PL);
  X.rotate(l->q_PL.toRotationMatrix());
  if (l->slide) {
    X.translate(-ref * l->axis_L);
  } else {
    X.translate(l->anchor_L);
    X.rotate(Eigen::AngleAxisd(-ref, l->axis_L));
    X.translate(-l->anchor_L);
  }
  l->p_PL = X.translation();
  l->q_PL = Eigen::Quaterniond(X.linear()).normalized();
}

}  // namespace

bool GeomShape(const mjModel* m, int g, Shape* s, std::string* error) {
  const mjtNum* size = m->geom_size + 3 * g;
  switch (m->geom_type[g]) {
    case mjGEOM_SPHERE: s->type = ShapeType::kSphere; s->size = {size[0], 0, 0}; break;
    case mjGEOM_CAPSULE: s->type = ShapeType::kCapsule; s->size = {size[0], size[1], 0}; break;
    case mjGEOM_CYLINDER: s->type = ShapeType::kCylinder; s->size = {size[0], size[1], 0}; break;
    case mjGEOM_BOX: s->type = ShapeType::kBox; s->size = Vec(size); break;
    case mjGEOM_ELLIPSOID: s->type = ShapeType::kEllipsoid; s->size = Vec(size); break;
    case mjGEOM_MESH:
      s->type = ShapeType::kConvex;
      if (!MeshHull(m, m->geom_dataid[g], s, error)) return false;
      break;
    default:
      *error = "is a plane or height field: use a box, sphere, capsule, cylinder, ellipsoid or mesh";
      return false;
  }
  s->p_LS = Vec(m->geom_pos + 3 * g);
  s->q_LS = Quat(m->geom_quat + 4 * g).normalized();
  return true;
}

void PostureFromQpos(const model::RobotMap& robot, const mjtNum* qpos, std::span<double> q) {
  const size_t na = robot.joints.size();
  for (size_t j = 0; j < na && j < q.size(); ++j) q[j] = qpos[robot.joints[j].qpos_adr];
  for (size_t k = 0; k < robot.passive.size() && na + k < q.size(); ++k)
    q[na + k] = qpos[robot.passive[k].qpos_adr];
}

bool GeometryFromModel(const mjModel* m, const model::RobotMap& robot, RobotGeometry* out,
                       std::string* error) {
  *out = RobotGeometry();
  out->name = robot.name;
  out->model_hash = model::ModelHash(m, robot);
  for (const auto& j : robot.joints) {
    out->joint_names.push_back(j.name);
    if (!Limits(m, j.joint_id, j.name, j.q_min, j.q_max, out, error)) return false;
  }
  // the passive joints (no actuator: read-only in the segment) come after the actuated ones
  for (const auto& p : robot.passive) {
    out->passive_names.push_back(p.name);
    const bool limited = m->jnt_limited[p.joint_id];
    const mjtNum* range = m->jnt_range + 2 * p.joint_id;
    if (!Limits(m, p.joint_id, p.name, limited ? range[0] : -model::kNoLimit,
                limited ? range[1] : model::kNoLimit, out, error))
      return false;
  }
  // the joint id of each MuJoCo joint: actuated, then passive
  std::map<int, int> segment_id;
  for (size_t i = 0; i < robot.joints.size(); ++i) segment_id[robot.joints[i].joint_id] = static_cast<int>(i);
  for (size_t k = 0; k < robot.passive.size(); ++k)
    segment_id[robot.passive[k].joint_id] = static_cast<int>(robot.joints.size() + k);
  std::map<int, int> link_of;  // MuJoCo body id -> link index (its last link)
  std::map<int, bool> left_out;  // bodies below a ball joint (and their subtrees)
  for (int b : model::RobotBodies(m, robot)) {
    const std::string body = Name(m, mjOBJ_BODY, b);
    const std::string where = "body '" + body + "'";
    if (left_out.count(m->body_parentid[b])) {
      left_out[b] = true;
      out->unchecked.push_back(body + ": below '" + Name(m, mjOBJ_BODY, m->body_parentid[b]) + "'");
      continue;
    }
    // a ball joint below the base: its orientation is not in the segment (only hinges and
    // slides are), so the body cannot be placed: left out, and said so
    const int nb = b == robot.base_body ? 0 : m->body_jntnum[b];
    bool ball = false;
    for (int j = m->body_jntadr[b]; j < m->body_jntadr[b] + nb; ++j) ball = ball || m->jnt_type[j] == mjJNT_BALL;
    if (ball) {
      left_out[b] = true;
      out->unchecked.push_back(body + ": a ball joint (its orientation is not in the segment)");
      continue;
    }
    const auto parent = link_of.find(m->body_parentid[b]);
    // the link being filled hangs from the body's parent at the body's pose; the base (a root)
    // is the frame of reference: it stays at the origin
    Link l;
    l.parent = parent == link_of.end() ? -1 : parent->second;
    if (l.parent >= 0 || b != robot.base_body) {
      l.p_PL = Vec(m->body_pos + 3 * b);
      l.q_PL = Quat(m->body_quat + 4 * b).normalized();
    }
    // its joints, in MuJoCo's order: each moves the body's frame as the ones before it left it,
    // a hinge turning it about its own axis through its own anchor, a slide translating it
    // along its axis (both in the body's frame). All but the last become links of their own
    // that carry no shapes (joint_only); the last carries the shapes.
    const int nj = b == robot.base_body ? 0 : m->body_jntnum[b], j0 = m->body_jntadr[b];
    for (int j = j0; j < j0 + nj; ++j) {
      const std::string jw = where + ": joint '" + Name(m, mjOBJ_JOINT, j) + "'";
      if (m->jnt_type[j] != mjJNT_HINGE && m->jnt_type[j] != mjJNT_SLIDE) {
        *error = jw + " is a free joint (below the base only hinges, slides and ball joints, "
                      "left out, are taken)";
        return false;
      }
      const auto id = segment_id.find(j);
      if (id == segment_id.end()) {
        *error = jw + " is neither one of the segment's joints nor one of its passive joints";
        return false;
      }
      if (j > j0) {  // the previous hinge's link is complete; this one hangs from it unmoved
        l.joint_only = true;
        l.name = body + "@" + Name(m, mjOBJ_JOINT, j - 1);
        out->links.push_back(std::move(l));
        l = Link();
        l.parent = static_cast<int>(out->links.size()) - 1;
      }
      l.joint = id->second;
      l.slide = m->jnt_type[j] == mjJNT_SLIDE;
      l.axis_L = Vec(m->jnt_axis + 3 * j).normalized();
      // a slide's anchor does not move anything
      l.anchor_L = l.slide ? Eigen::Vector3d::Zero() : Vec(m->jnt_pos + 3 * j);
      RebaseToZero(m, j, &l);
    }
    l.name = body;
    // its geoms, each shape once
    const int g0 = m->body_geomadr[b];
    for (int g = g0; g < g0 + m->body_geomnum[b]; ++g) {
      bool twice = false;
      for (int h = g0; h < g && !twice; ++h) twice = SameGeom(m, g, h);
      if (twice) continue;
      Shape s;
      std::string why;
      if (!GeomShape(m, g, &s, &why)) {
        *error = where + ": geom " + std::to_string(g) + " '" + Name(m, mjOBJ_GEOM, g) + "' " + why;
        return false;
      }
      l.shapes.push_back(std::move(s));
    }
    link_of[b] = static_cast<int>(out->links.size());
    out->links.push_back(std::move(l));
  }
  const std::string problem = Validate(*out);
  if (!problem.empty()) *error = problem;
  return problem.empty();
}

}  // namespace ohrp::collision
