// The collision geometry of a robot's links: a kinematic tree of rigid links, each with convex
// shapes fixed in its frame, in the joint order of the segment. It is plain data, built from an
// MJCF (collision/from_mjcf.h) or read from a self-collision file (collision/pair_file.h), so a
// controller needs no MuJoCo to check its postures. SI units: metres, radians.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace ohrp::collision {

// the convex shapes the checker handles
enum class ShapeType { kSphere, kCapsule, kCylinder, kBox, kConvex, kEllipsoid };

// "sphere", "capsule", "cylinder", "box", "convex", "ellipsoid"
const char* ShapeName(ShapeType type);
// the type of a name of ShapeName; false when unknown
bool ParseShape(const std::string& name, ShapeType* type);

// one convex shape of a link
struct Shape {
  ShapeType type = ShapeType::kSphere;
  // sphere: (radius, -, -); capsule and cylinder: (radius, half-length along z, -);
  // box: half-sizes along x, y, z; ellipsoid: semi-axes along x, y, z [m]
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  Eigen::Vector3d p_LS = Eigen::Vector3d::Zero();                 // position in the link frame [m]
  Eigen::Quaterniond q_LS = Eigen::Quaterniond::Identity();       // orientation in the link frame
  std::vector<Eigen::Vector3d> vertices;  // convex: the hull's vertices in the shape frame [m]
  std::vector<int> faces;  // convex: per face, its vertex count then its vertex indices (FCL's)
};

// one rigid link: its pose in its parent at zero joint position, then its joint: a hinge about
// `axis_L` through `anchor_L` (both in this link's frame), a slide along `axis_L` (the link
// translated by q axis_L), or no joint (welded to its parent)
struct Link {
  std::string name;
  int parent = -1;   // index of the parent link, -1 for a root (the base: its frame is the world)
  Eigen::Vector3d p_PL = Eigen::Vector3d::Zero();            // position in the parent [m]
  Eigen::Quaterniond q_PL = Eigen::Quaterniond::Identity();  // orientation in the parent
  int joint = -1;    // the joint id of its joint (RobotGeometry), -1 when welded or the base
  bool slide = false;  // the joint is a slide (q in metres), not a hinge (q in radians)
  Eigen::Vector3d axis_L = Eigen::Vector3d::UnitZ();         // joint axis (unit) in the link
  Eigen::Vector3d anchor_L = Eigen::Vector3d::Zero();        // hinge: a point on the axis [m]
  std::vector<Shape> shapes;
  // A body with several joints (MuJoCo's humanoid: a hip of three hinges) is a chain of links,
  // one joint each: the first ones carry no shapes and are joint_only, the last carries the
  // body's shapes and its name. A joint_only link and its child are one body: the body's parent
  // and the link with its shapes are adjacent (BodyParent).
  bool joint_only = false;
};

// a robot's links in topological order (a parent before its children) and its joints.
// Joint ids: 0..njoint-1 are the segment's (actuated) joints, in the segment's order;
// njoint..njoint+npassive-1 its passive joints (no actuator drives them: the segment publishes
// them read-only, SensorBlock::passive_q, in the order of SegmentHeader::passive_names). A
// posture is njoint + npassive values (NumJoints), actuated then passive: the guard cannot
// command a passive joint, but it moves its links, within its limits.
struct RobotGeometry {
  std::string name;
  uint64_t model_hash = 0;                 // robot_model/model_hash.h of the model it came from
  std::vector<std::string> joint_names;    // actuated joints, by segment joint id
  std::vector<std::string> passive_names;  // passive joints: joint id njoint + k
  std::vector<double> q_min, q_max;        // limits by joint id, actuated then passive [rad, m]
  std::vector<Link> links;
  // parts of the robot the geometry leaves out, each "BODY: why" (e.g. a body below a ball
  // joint, whose orientation the segment does not publish): never checked
  std::vector<std::string> unchecked;
};

// the length of a posture: actuated plus passive joints
inline int NumJoints(const RobotGeometry& r) {
  return static_cast<int>(r.joint_names.size() + r.passive_names.size());
}

// the name of joint id `j` (actuated or passive)
const std::string& JointName(const RobotGeometry& r, int j);

// the joint id of a joint name (actuated or passive), -1 when there is none
int FindJoint(const RobotGeometry& r, const std::string& name);

// a pair of links by index, a < b
struct LinkPair {
  int a = -1, b = -1;
  bool operator==(const LinkPair& o) const { return a == o.a && b == o.b; }
};

// The link of the body `link` hangs from: its parent, past the joint_only links of its own
// body; -1 for a root.
int BodyParent(const RobotGeometry& robot, int link);

// Every pair of links that is not parent and child (BodyParent), in order (a, then b). Links
// without shapes are left out.
std::vector<LinkPair> NonAdjacentPairs(const RobotGeometry& robot);

// The link index of `name`, -1 when there is none.
int FindLink(const RobotGeometry& robot, const std::string& name);

// Checks the geometry: limits for every joint (actuated and passive), parents before children,
// joint ids in range, unit axes and quaternions,
// joint_only links with a joint and no shapes, slides with finite limits, positive sizes,
// convex shapes with vertices.
// Returns an empty string or what is wrong.
std::string Validate(const RobotGeometry& robot);

}  // namespace ohrp::collision
