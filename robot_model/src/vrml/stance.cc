// Forward kinematics of the VRML tree at set-up (see stance.h).
#include "vrml/stance.h"

#include <algorithm>
#include <cmath>

namespace ohrp::vrml {
namespace {

// the lowest point of a box geom in the world, its body at `world`
double LowestPoint(const Geom& g, const Pose& world) {
  const Pose p = Compose(world, g.pose);
  const Eigen::Matrix3d R = p.q.toRotationMatrix();
  double reach = 0;
  for (int k = 0; k < 3; ++k) reach += std::fabs(R(2, k)) * g.size[k];
  return p.p.z() - reach;
}

// the body's joint at angle q[name], then its named geoms and its children
void NamedBottoms(const Body& b, const Pose& world_in, const std::map<std::string, double>& q,
                  double* lowest) {
  Pose world = world_in;
  auto it = q.find(b.joint.name);
  const double angle = it == q.end() ? 0.0 : it->second;
  if (b.joint.type == Joint::kHinge) {
    Pose r;
    r.q = Eigen::Quaterniond(Eigen::AngleAxisd(angle, b.joint.axis));
    world = Compose(world, r);
  } else if (b.joint.type == Joint::kSlide) {
    Pose t;
    t.p = b.joint.axis * angle;
    world = Compose(world, t);
  }
  for (const Geom& g : b.geoms)
    if (!g.name.empty()) *lowest = std::min(*lowest, LowestPoint(g, world));
  for (const auto& c : b.children) NamedBottoms(*c, Compose(world, c->pose), q, lowest);
}

}  // namespace

Body* FindBody(Body* b, const std::string& name) {
  if (b->name == name) return b;
  for (auto& c : b->children)
    if (Body* f = FindBody(c.get(), name)) return f;
  return nullptr;
}

Geom* LowestBox(Body* b, const Pose& pose, double* lowest) {
  Geom* best = nullptr;
  for (Geom& g : b->geoms) {
    if (g.type != Geom::kBox) continue;
    const double z = LowestPoint(g, pose);
    if (z < *lowest) {
      *lowest = z;
      best = &g;
    }
  }
  for (auto& c : b->children) {
    Geom* g = LowestBox(c.get(), Compose(pose, c->pose), lowest);
    if (g) best = g;
  }
  return best;
}

double LowestNamedPoint(const Body& root, const std::map<std::string, double>& q) {
  double lowest = 1e300;
  Pose start;
  start.q = root.pose.q;
  NamedBottoms(root, start, q, &lowest);
  return lowest;
}

}  // namespace ohrp::vrml
