// Bounds of each joint's inertia and gravity torque over every posture, from the model's bodies.
#include "collision/joint_dynamics.h"

#include <algorithm>
#include <cmath>

#include "robot_model/model_hash.h"

namespace ohrp::collision {
namespace {

double Norm3(const mjtNum* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// how far the frame of body c can be from its parent's frame in any posture [m]: its offset,
// plus for each of its hinges twice the anchor's offset (a turn about a point off the origin
// moves the origin by at most that), for each slide its travel
double EdgeLength(const mjModel* m, int c) {
  double l = Norm3(m->body_pos + 3 * c);
  for (int j = m->body_jntadr[c]; j < m->body_jntadr[c] + m->body_jntnum[c]; ++j) {
    if (m->jnt_type[j] == mjJNT_HINGE) l += 2 * Norm3(m->jnt_pos + 3 * j);
    if (m->jnt_type[j] == mjJNT_SLIDE)
      l += std::max(std::abs(m->jnt_range[2 * j]), std::abs(m->jnt_range[2 * j + 1]));
  }
  return l;
}

// a body's own bound: mass times reach squared plus its largest principal inertia, and the
// gravity lever
struct Side {
  double inertia = 0;   // [kg m^2]
  double moment = 0;    // sum m r [kg m]
  double mass = 0;      // [kg]
  double inertia_min = 0;  // sum of the smallest principal inertias [kg m^2]
  void Add(const mjModel* m, int b, double r) {
    const mjtNum* I = m->body_inertia + 3 * b;
    inertia += m->body_mass[b] * r * r + std::max({I[0], I[1], I[2]});
    inertia_min += std::min({I[0], I[1], I[2]});
    moment += m->body_mass[b] * r;
    mass += m->body_mass[b];
  }
};

}  // namespace

std::vector<char> SupportBodies(const mjModel* m, const model::RobotMap& robot) {
  const std::vector<int> bodies = model::RobotBodies(m, robot);
  mjData* d = mj_makeData(m);
  mj_kinematics(m, d);  // qpos0
  // per body, the lowest point of its geoms' bounding spheres; the robot's lowest and highest
  std::vector<double> low(m->nbody, INFINITY);
  double bottom = INFINITY, top = -INFINITY;
  for (int b : bodies)
    for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
      const double z = d->geom_xpos[3 * g + 2], r = m->geom_rbound[g];
      low[b] = std::min(low[b], z - r);
      bottom = std::min(bottom, z - r);
      top = std::max(top, z + r);
    }
  mj_deleteData(d);
  std::vector<char> support(m->nbody, 0);
  for (int b : bodies) support[b] = low[b] <= bottom + 0.1 * (top - bottom);
  return support;
}

std::vector<JointDynamics> JointDynamicsFromModel(const mjModel* m, const model::RobotMap& robot) {
  const std::vector<int> bodies = model::RobotBodies(m, robot);
  const auto in_robot = [&](int b) { return std::find(bodies.begin(), bodies.end(), b) != bodies.end(); };
  // the chain of robot bodies from b up to the robot's root (b first)
  const auto chain = [&](int b) {
    std::vector<int> c;
    for (; b > 0 && in_robot(b); b = m->body_parentid[b]) c.push_back(b);
    return c;
  };
  const double g = Norm3(m->opt.gravity);
  const std::vector<char> support = SupportBodies(m, robot);
  std::vector<JointDynamics> out;
  for (const auto& jm : robot.joints) {
    const int j = jm.joint_id, jb = m->jnt_bodyid[j], dof = jm.dof_adr;
    const bool slide = m->jnt_type[j] == mjJNT_SLIDE;
    const double anchor = slide ? 0.0 : Norm3(m->jnt_pos + 3 * j);
    const std::vector<int> up_j = chain(jb);
    Side beyond, rest;
    bool carries = false;  // the links beyond include a support: standing on them, the joint
                           // drives the rest of the robot
    for (int b : bodies) {
      const std::vector<int> up_b = chain(b);
      const bool below = std::find(up_b.begin(), up_b.end(), jb) != up_b.end();
      // the path between jb and b through their lowest common body: the edges of each chain
      // below it; jb's own edge counts on the way up (jb turns about the joint)
      double r = anchor + Norm3(m->body_ipos + 3 * b);
      if (below) {
        for (int c : up_b) {
          if (c == jb) break;
          r += EdgeLength(m, c);
        }
        r += EdgeLength(m, jb) - Norm3(m->body_pos + 3 * jb);  // jb's other joints' anchors
      } else {
        int common = -1;
        for (int c : up_j)
          if (std::find(up_b.begin(), up_b.end(), c) != up_b.end()) { common = c; break; }
        for (int c : up_j) {
          if (c == common) break;
          r += EdgeLength(m, c);
        }
        for (int c : up_b) {
          if (c == common) break;
          r += EdgeLength(m, c);
        }
      }
      if (slide) r = 0;  // a slide's load is its mass; no lever
      (below ? beyond : rest).Add(m, b, r);
      carries = carries || (below && support[b]);
    }
    // the force sensor beyond the joint, where the links beyond stand
    std::string sensor;
    for (const auto& f : robot.forces) {
      int up = m->site_bodyid[f.site_id];
      while (up > 0 && up != jb) up = m->body_parentid[up];
      if (up == jb && sensor.empty()) sensor = f.name;
    }
    if (!carries) rest = Side();
    JointDynamics d;
    d.inertia_free = m->dof_armature[dof] + (slide ? beyond.mass : beyond.inertia);
    if (carries) {
      // a foot without a force sensor: "none", which no segment names, so the guard takes the
      // leg as always loaded and never brakes it (it cannot tell a swing foot from a stance one)
      d.support_sensor = sensor.empty() ? "none" : sensor;
      d.support_force = 0.1 * g * robot.total_mass;
    }
    const double armature = m->dof_armature[dof];
    if (slide) {
      d.inertia_max = armature + std::max(beyond.mass, rest.mass);
      d.inertia_min = armature > 0 ? armature : std::min(beyond.mass, d.inertia_free);
      d.gravity_max = g * std::max(beyond.mass, rest.mass);
    } else {
      d.inertia_max = armature + std::max(beyond.inertia, rest.inertia);
      d.inertia_min = armature > 0 ? armature : std::min(beyond.inertia_min, d.inertia_free);
      d.gravity_max = g * std::max(beyond.moment, rest.moment);
    }
    d.damping = m->dof_damping[dof];
    d.velocity_max = 0;
    out.push_back(d);
  }
  return out;
}

}  // namespace ohrp::collision
