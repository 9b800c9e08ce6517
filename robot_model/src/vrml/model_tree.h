// The kinematic tree read from OpenHRP VRML documents: bodies (one per Joint) with their joint,
// inertia, geometry, sensor sites and cameras, in SI units and radians, poses in the parent
// body's frame. Built by BuildModel from parsed documents; written out by WriteMjcf.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "vrml/syntax.h"

namespace ohrp::vrml {

// a frame: position and orientation in the parent frame
struct Pose {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
};
Pose Compose(const Pose& a, const Pose& b);  // b expressed in a, to a's parent

struct Geom {
  enum Type { kBox, kCylinder, kSphere, kMesh };
  Type type = kBox;
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // MJCF sizes (half edges; radius, half height)
  Pose pose;                                        // in the body frame
  bool has_rgba = false;
  Eigen::Vector4d rgba = Eigen::Vector4d::Ones();
  int mesh = -1;     // index into Model::meshes (kMesh)
  std::string name;  // set for the soles
};

struct Mesh {
  std::vector<double> vertices;  // x y z per vertex, in the geom frame [m]
  std::vector<int> faces;        // triangles
};

struct Site {
  enum Kind { kForce, kGyro, kAccel };
  Kind kind = kForce;
  std::string name;
  Pose pose;
  int sensor_id = -1;
};

struct Camera {
  std::string name;
  Pose pose;
  double fov = 0.785398;  // fieldOfView [rad]
  int sensor_id = -1;
};

struct Joint {
  enum Type { kNone, kFree, kHinge, kSlide };
  Type type = kNone;
  std::string name;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int id = -1;  // jointId; -1: passive
  bool has_range = false;
  double lower = 0, upper = 0;  // [rad or m]
  double armature = 0;          // rotorInertia * gearRatio^2 [kg m^2 or kg]
  double stiffness = 0;         // first value of `stiffness` [N m/rad or N/m]
  Where at;
};

struct Segment {
  double mass = 0;                                    // [kg]
  Eigen::Vector3d com = Eigen::Vector3d::Zero();      // in the body frame [m]
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the CoM, body axes [kg m^2]
  std::string name;
};

struct Body {
  std::string name;
  Pose pose;  // in the parent body (the root: in the world)
  Joint joint;
  std::vector<Segment> segments;
  std::vector<Geom> geoms;
  std::vector<Site> sites;
  std::vector<Camera> cameras;
  std::vector<std::unique_ptr<Body>> children;
};

// one Humanoid (or top-level Joint) of the scene
struct Object {
  std::string name;  // the Humanoid's DEF name or name field
  std::string file;  // for messages
  std::unique_ptr<Body> root;
  bool robot = false;  // the first object with jointIds: its motors are the segment's joints
};

struct Model {
  std::string name;  // the robot's name (else the first object's)
  std::vector<Object> objects;
  std::vector<Geom> world_geoms;  // top-level Transform/Shape scenery
  std::vector<Mesh> meshes;
};

// one parsed file of the scene
struct SourceDocument {
  std::string file;
  Document doc;
};

// Builds the model from the documents (the main file first, then its Inline files). Returns
// false with `*error` = "file:line:column: ..." on what cannot be represented (an unknown
// jointType, a bad jointAxis, momentsOfInertia without 9 numbers, a duplicate jointId, a
// scene larger than kMaxElements bodies and geoms, no Humanoid or Joint at all).
bool BuildModel(const std::vector<SourceDocument>& docs, Model* model, std::string* error);

inline constexpr int kMaxElements = 20000;  // bodies + geoms + sites a scene may expand to

}  // namespace ohrp::vrml
