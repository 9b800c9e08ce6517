// The plain geometry: shape names, the non-adjacent pairs, lookup and validation.
#include "collision/geometry.h"

#include <cmath>
#include <sstream>

namespace ohrp::collision {

const char* ShapeName(ShapeType type) {
  switch (type) {
    case ShapeType::kSphere: return "sphere";
    case ShapeType::kCapsule: return "capsule";
    case ShapeType::kCylinder: return "cylinder";
    case ShapeType::kBox: return "box";
    case ShapeType::kConvex: return "convex";
    case ShapeType::kEllipsoid: return "ellipsoid";
  }
  return "?";
}

bool ParseShape(const std::string& name, ShapeType* type) {
  for (ShapeType t : {ShapeType::kSphere, ShapeType::kCapsule, ShapeType::kCylinder,
                      ShapeType::kBox, ShapeType::kConvex, ShapeType::kEllipsoid}) {
    if (name == ShapeName(t)) {
      *type = t;
      return true;
    }
  }
  return false;
}

const std::string& JointName(const RobotGeometry& r, int j) {
  const int n = static_cast<int>(r.joint_names.size());
  return j < n ? r.joint_names[j] : r.passive_names[j - n];
}

int FindJoint(const RobotGeometry& r, const std::string& name) {
  for (int j = 0; j < NumJoints(r); ++j)
    if (JointName(r, j) == name) return j;
  return -1;
}

int BodyParent(const RobotGeometry& robot, int link) {
  int p = robot.links[link].parent;
  while (p >= 0 && robot.links[p].joint_only) p = robot.links[p].parent;
  return p;
}

std::vector<LinkPair> NonAdjacentPairs(const RobotGeometry& robot) {
  std::vector<LinkPair> pairs;
  const int n = static_cast<int>(robot.links.size());
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      // parent and child are never checked: their joints' ranges keep them apart (the paper)
      if (BodyParent(robot, b) == a || BodyParent(robot, a) == b) continue;
      if (robot.links[a].shapes.empty() || robot.links[b].shapes.empty()) continue;
      pairs.push_back({a, b});
    }
  }
  return pairs;
}

int FindLink(const RobotGeometry& robot, const std::string& name) {
  for (size_t i = 0; i < robot.links.size(); ++i)
    if (robot.links[i].name == name) return static_cast<int>(i);
  return -1;
}

std::string Validate(const RobotGeometry& robot) {
  std::ostringstream e;
  const int njoint = NumJoints(robot);
  if (static_cast<int>(robot.q_min.size()) != njoint || static_cast<int>(robot.q_max.size()) != njoint)
    return "the joint limits do not match the joint names (one min and max per joint, actuated "
           "then passive)";
  for (int j = 0; j < njoint; ++j)
    if (!(robot.q_min[j] <= robot.q_max[j]))
      return "joint '" + JointName(robot, j) + "': its min exceeds its max";
  for (size_t i = 0; i < robot.links.size(); ++i) {
    const Link& l = robot.links[i];
    const std::string where = "link " + std::to_string(i) + " '" + l.name + "': ";
    // the tree: parents come first
    if (l.parent >= static_cast<int>(i) || l.parent < -1)
      return where + "its parent " + std::to_string(l.parent) + " is not an earlier link";
    if (l.joint < -1 || l.joint >= njoint)
      return where + "joint id " + std::to_string(l.joint) + " is outside 0.." +
             std::to_string(njoint - 1);
    if (l.joint >= 0 && std::abs(l.axis_L.norm() - 1) > 1e-6)
      return where + "its joint axis is not a unit vector";
    if (l.joint_only && (l.joint < 0 || !l.shapes.empty()))
      return where + "a joint_only link needs a joint and no shapes";
    if (l.slide && l.joint < 0) return where + "a slide needs a joint";
    // a slide's travel bounds how far its link moves (LinkReach)
    if (l.slide && !(std::isfinite(robot.q_min[l.joint]) && std::isfinite(robot.q_max[l.joint])))
      return where + "its slide joint '" + JointName(robot, l.joint) +
             "' has no finite limits: give it a range";
    if (std::abs(l.q_PL.norm() - 1) > 1e-6 || !l.p_PL.allFinite())
      return where + "its pose in the parent is not finite with a unit quaternion";
    // the shapes: positive sizes, vertices for a convex hull
    for (size_t s = 0; s < l.shapes.size(); ++s) {
      const Shape& sh = l.shapes[s];
      const int nsize = sh.type == ShapeType::kBox || sh.type == ShapeType::kEllipsoid ? 3
                        : sh.type == ShapeType::kSphere ? 1
                        : sh.type == ShapeType::kConvex ? 0 : 2;
      for (int k = 0; k < nsize; ++k)
        if (!(sh.size[k] > 0) || !std::isfinite(sh.size[k]))
          return where + "shape " + std::to_string(s) + " (" + ShapeName(sh.type) +
                 ") has a size that is not positive";
      if (sh.type == ShapeType::kConvex && (sh.vertices.size() < 4 || sh.faces.empty()))
        return where + "shape " + std::to_string(s) + " is a convex hull without vertices or faces";
      if (std::abs(sh.q_LS.norm() - 1) > 1e-6 || !sh.p_LS.allFinite())
        return where + "shape " + std::to_string(s) + " has a non-unit quaternion or bad position";
    }
  }
  return "";
}

}  // namespace ohrp::collision
