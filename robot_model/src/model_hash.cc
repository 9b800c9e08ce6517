// The robot model's identity: its hash, the header fields that go with it, and the check a
// controller runs against a producer's header (see model_hash.h).
#include "robot_model/model_hash.h"

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "shm_bridge/checks.h"

namespace ohrp::model {
namespace {

//---------------- feeding the hash ----------------

// FNV-1a over values fed one by one, independent of the host's byte order
class Hasher {
 public:
  void Int(int64_t v) {
    const uint64_t u = static_cast<uint64_t>(v);
    for (int i = 0; i < 8; ++i) {
      const char byte = static_cast<char>((u >> (8 * i)) & 0xffu);
      h_ = shm::Fnv1a64(&byte, 1, h_);
    }
  }
  // the bits of `v`, with -0.0 made 0.0 (they compare equal, they must hash equal)
  void Real(double v) {
    if (v == 0.0) v = 0.0;
    uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof(bits));
    Int(static_cast<int64_t>(bits));
  }
  void Reals(const double* v, int n) {
    for (int i = 0; i < n; ++i) Real(v[i]);
  }
  // length first, so that ("ab", "c") and ("a", "bc") differ
  void Name(const char* s) {
    const std::size_t n = s != nullptr ? std::strlen(s) : 0;
    Int(static_cast<int64_t>(n));
    if (n > 0) h_ = shm::Fnv1a64(s, n, h_);
  }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = shm::kFnv1aOffsetBasis;
};

// degrees of freedom of a joint of type `type`
int DofCount(int type) {
  switch (type) {
    case mjJNT_FREE: return 6;
    case mjJNT_BALL: return 3;
    default: return 1;
  }
}

bool HasFreeJoint(const mjModel* m, int body) {
  for (int k = 0; k < m->body_jntnum[body]; ++k) {
    if (m->jnt_type[m->body_jntadr[body] + k] == mjJNT_FREE) return true;
  }
  return false;
}

// body b's geoms: their count, and each one's type, size, pose in the body and, for a mesh, its
// vertices (not colours, contact parameters or groups: the same shapes with another friction
// hash the same)
void HashGeoms(const mjModel* m, int b, Hasher* h) {
  h->Int(m->body_geomnum[b]);
  for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
    h->Int(m->geom_type[g]);
    h->Reals(m->geom_size + 3 * g, 3);
    h->Reals(m->geom_pos + 3 * g, 3);
    h->Reals(m->geom_quat + 4 * g, 4);
    if (m->geom_type[g] != mjGEOM_MESH || m->geom_dataid[g] < 0) continue;
    const int mesh = m->geom_dataid[g];
    h->Int(m->mesh_vertnum[mesh]);
    const float* v = m->mesh_vert + 3 * m->mesh_vertadr[mesh];
    for (int i = 0; i < 3 * m->mesh_vertnum[mesh]; ++i) h->Real(v[i]);
  }
}

//---------------- message helpers ----------------

std::string Hex(uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof(text), "0x%016llx", static_cast<unsigned long long>(v));
  return text;
}

std::string Num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", v);
  return text;
}

std::string Vec3(const double* v) {
  char text[96];
  std::snprintf(text, sizeof(text), "(%.9g, %.9g, %.9g)", v[0], v[1], v[2]);
  return text;
}

std::string JointLabel(int i, const std::string& name) {
  return "joint " + std::to_string(i) + " '" + name + "'";
}

double TotalMass(const mjModel* m, const std::vector<int>& bodies) {
  double mass = 0.0;
  for (int b : bodies) mass += m->body_mass[b];
  return mass;
}

// the first difference between the header and this model, or "" when none of the named
// quantities differ
std::string FirstDifference(const mjModel* m, const RobotMap& robot, const shm::SegmentHeader& h) {
  const int n = static_cast<int>(robot.joints.size());
  if (h.njoint != n) {
    return "the segment has " + std::to_string(h.njoint) + " joints, this model " +
           std::to_string(n);
  }
  for (int i = 0; i < n; ++i) {
    if (robot.joints[i].name != h.joint_names[i]) {
      return "joint " + std::to_string(i) + " is '" + h.joint_names[i] + "' in the segment, '" +
             robot.joints[i].name + "' here";
    }
  }
  for (int i = 0; i < n; ++i) {
    const JointMap& j = robot.joints[i];
    if (j.q_min != h.q_min[i] || j.q_max != h.q_max[i]) {
      return JointLabel(i, j.name) + " limits are [" + Num(h.q_min[i]) + ", " + Num(h.q_max[i]) +
             "] in the segment, [" + Num(j.q_min) + ", " + Num(j.q_max) + "] here [rad or m]";
    }
  }
  for (int i = 0; i < n; ++i) {
    const double* axis = m->jnt_axis + 3 * robot.joints[i].joint_id;
    if (axis[0] != h.joint_axis[i][0] || axis[1] != h.joint_axis[i][1] ||
        axis[2] != h.joint_axis[i][2]) {
      return JointLabel(i, robot.joints[i].name) + " axis is " + Vec3(h.joint_axis[i]) +
             " in the segment, " + Vec3(axis) + " here (in its body's frame)";
    }
  }
  for (int i = 0; i < n; ++i) {
    const double mass = m->body_mass[m->jnt_bodyid[robot.joints[i].joint_id]];
    if (mass != h.link_mass[i]) {
      return JointLabel(i, robot.joints[i].name) + " moves a body of " + Num(h.link_mass[i]) +
             " kg in the segment, " + Num(mass) + " kg here";
    }
  }
  const std::vector<int> bodies = RobotBodies(m, robot);
  const double total = TotalMass(m, bodies);
  if (total != h.total_mass) {
    return "the robot's total mass is " + Num(h.total_mass) + " kg in the segment, " +
           Num(total) + " kg here";
  }
  if (static_cast<int>(bodies.size()) != h.nbody) {
    return "the robot has " + std::to_string(h.nbody) + " bodies in the segment, " +
           std::to_string(bodies.size()) + " here";
  }
  return "";
}

}  // namespace

//---------------- the robot's bodies and its hash ----------------

std::vector<int> RobotBodies(const mjModel* m, const RobotMap& robot) {
  std::vector<int> bodies;
  for (int b = 1; b < m->nbody; ++b) {
    if (robot.base_body < 0) {
      bodies.push_back(b);
      continue;
    }
    // in the base's subtree: the base is among its ancestors (the world is its own parent)
    int a = b;
    while (a != robot.base_body && a != 0) a = m->body_parentid[a];
    if (a == robot.base_body) bodies.push_back(b);
  }
  return bodies;
}

uint64_t ModelHash(const mjModel* m, const RobotMap& robot) {
  const std::vector<int> bodies = RobotBodies(m, robot);
  // index of each body among the robot's bodies (-1: not one of them, e.g. the world)
  std::vector<int> local(static_cast<std::size_t>(m->nbody), -1);
  for (std::size_t i = 0; i < bodies.size(); ++i) local[bodies[i]] = static_cast<int>(i);

  Hasher h;
  h.Int(static_cast<int64_t>(bodies.size()));
  for (int b : bodies) {
    // the body in its parent, and its inertia
    h.Int(local[m->body_parentid[b]]);
    if (!HasFreeJoint(m, b)) {
      h.Reals(m->body_pos + 3 * b, 3);
      h.Reals(m->body_quat + 4 * b, 4);
    }
    h.Real(m->body_mass[b]);
    h.Reals(m->body_inertia + 3 * b, 3);
    h.Reals(m->body_ipos + 3 * b, 3);
    h.Reals(m->body_iquat + 4 * b, 4);
    // its joints
    h.Int(m->body_jntnum[b]);
    for (int k = 0; k < m->body_jntnum[b]; ++k) {
      const int j = m->body_jntadr[b] + k;
      h.Int(m->jnt_type[j]);
      h.Name(mj_id2name(m, mjOBJ_JOINT, j));
      h.Reals(m->jnt_axis + 3 * j, 3);
      h.Reals(m->jnt_pos + 3 * j, 3);
      h.Int(m->jnt_limited[j]);
      h.Reals(m->jnt_range + 2 * j, 2);
      for (int d = 0; d < DofCount(m->jnt_type[j]); ++d) {
        h.Real(m->dof_armature[m->jnt_dofadr[j] + d]);
        h.Real(m->dof_damping[m->jnt_dofadr[j] + d]);
      }
    }
  }
  // the collision geometry the self-collision checker takes from every body (collision/from_mjcf.h)
  for (int b : bodies) HashGeoms(m, b, &h);
  // the segment's joint order
  h.Int(static_cast<int64_t>(robot.joints.size()));
  for (const JointMap& j : robot.joints) h.Name(j.name.c_str());
  return h.value();
}

void FillModelIdentity(const mjModel* m, const RobotMap& robot, shm::ProducerConfig* config) {
  const std::vector<int> bodies = RobotBodies(m, robot);
  config->model_hash = ModelHash(m, robot);
  config->nbody = static_cast<int>(bodies.size());
  config->total_mass = TotalMass(m, bodies);
  config->joint_axis.clear();
  config->link_mass.clear();
  for (const JointMap& j : robot.joints) {
    const double* axis = m->jnt_axis + 3 * j.joint_id;
    config->joint_axis.push_back({axis[0], axis[1], axis[2]});
    config->link_mass.push_back(m->body_mass[m->jnt_bodyid[j.joint_id]]);
  }
}

//---------------- the controller's check ----------------

std::string CheckModelMatches(const mjModel* m, const RobotMap& robot,
                              const shm::SegmentHeader& header) {
  const uint64_t here = ModelHash(m, robot);
  if (header.model_hash == here) return "";
  const shm::SegmentHeader h = shm::SanitizedHeader(header);
  const std::string hashes =
      "; model hash " + Hex(h.model_hash) + " in the segment, " + Hex(here) + " here";
  if (h.model_hash == 0) {
    return "the producer publishes no model hash, so its robot cannot be checked against this "
           "model (a producer built before layout version 2 or one that leaves the model "
           "identity empty)" + hashes;
  }

  std::string message = "the producer's robot is not this model's robot";
  if (robot.name != h.robot_name) {
    message += " (model names, not compared: '" + std::string(h.robot_name) +
               "' in the segment, '" + robot.name + "' here)";
  }
  std::string difference = FirstDifference(m, robot, h);
  if (difference.empty()) {
    difference = "same joints, limits, axes and masses, but the kinematic tree differs (body "
                 "positions, inertias or passive joints)";
  }
  return message + ": " + difference + hashes;
}

}  // namespace ohrp::model
