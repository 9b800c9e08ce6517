// The kinematic tree from parsed OpenHRP VRML documents (see model_tree.h). A VRML Transform
// (and Joint, and a sensor) is T(translation) T(center) R(rotation) T(-center); the frames of
// Transforms between two Joints are composed into the child body's pose; shapes and segments
// below them get the composed pose in their body.
#include <Eigen/Eigenvalues>
#include <cmath>

#include "cli/plausible.h"
#include "vrml/model_tree.h"

namespace ohrp::vrml {

Pose Compose(const Pose& a, const Pose& b) {
  Pose out;
  out.p = a.p + a.q * b.p;
  out.q = (a.q * b.q).normalized();
  return out;
}

namespace {

constexpr int kMaxVisitDepth = 1000;  // nesting through DEF/USE a scene may reach
constexpr long kMaxVisits = 1000000;  // nodes visited, repeats by USE included

// a name as MJCF may carry it in an attribute: XML's special characters become '_'
std::string CleanName(std::string name) {
  for (char& c : name) {
    if (c == '&' || c == '<' || c == '>' || c == '"' || c == '\'' ||
        static_cast<unsigned char>(c) < 0x20)
      c = '_';
  }
  return name;
}

class Builder {
 public:
  Builder(Model* model, std::string* error) : model_(model), error_(error) {}

  bool Document(const SourceDocument& src) {
    file_ = src.file;
    for (const NodePtr& node : src.doc.roots) {
      if (node->type == "Humanoid") {
        Pose pose;
        if (!TransformPose(*node, &pose)) return false;
        for (const NodePtr& b : node->Nodes("humanoidBody")) {
          if (b->type != "Joint") continue;
          std::string name = node->String("name", "");
          if (name.empty()) name = node->def_name;
          if (!Object(*b, pose, name.empty() ? b->def_name : name)) return false;
        }
      } else if (node->type == "Joint") {
        if (!Object(*node, Pose{}, node->def_name)) return false;
      } else {
        // scenery outside any Humanoid: static geometry of the world
        Body world;
        if (!Visit(*node, Pose{}, &world, 0)) return false;
        for (auto& g : world.geoms) model_->world_geoms.push_back(g);
      }
    }
    return true;
  }

  bool Finish() {
    if (model_->objects.empty() && model_->world_geoms.empty())
      return Fail(Where{}, "no Humanoid, Joint or Shape found: an OpenHRP model has a "
                           "Humanoid { humanoidBody [ DEF WAIST Joint { ... } ] }");
    for (auto& o : model_->objects) {
      if (HasJointIds(*o.root)) {
        o.robot = true;
        model_->name = o.name;
        break;
      }
    }
    if (model_->name.empty() && !model_->objects.empty()) model_->name = model_->objects[0].name;
    if (model_->name.empty()) model_->name = "vrml";
    return true;
  }

 private:
  // `value`, the number of the file at `at` that `what` names, within the plausible range of
  // `quantity` (cli/plausible.h): an absurd but finite number is refused with the range
  bool Plausible(const Where& at, const char* quantity, double value, const std::string& what) {
    const std::string e = cli::CheckPlausible(quantity, value, what);
    return e.empty() || Fail(at, e);
  }

  bool Fail(const Where& at, const std::string& what) {
    *error_ = file_ + ":" + At(at) + what;
    return false;
  }

  static bool HasJointIds(const Body& b) {
    if (b.joint.id >= 0) return true;
    for (const auto& c : b.children)
      if (HasJointIds(*c)) return true;
    return false;
  }

  // a field of exactly n numbers
  bool Vec(const Node& n, const char* field, int count, double* out, bool* present = nullptr) {
    const Value* v = n.Field(field);
    if (present) *present = v != nullptr;
    if (!v) return true;
    if (v->kind != Value::kNumbers || static_cast<int>(v->numbers.size()) != count)
      return Fail(v->at, std::string(n.type) + "." + field + " needs " + std::to_string(count) +
                             " numbers");
    for (int k = 0; k < count; ++k) out[k] = v->numbers[k];
    return true;
  }

  bool Rotation(const Node& n, const char* field, Eigen::Quaterniond* q) {
    double r[4] = {0, 0, 1, 0};
    if (!Vec(n, field, 4, r)) return false;
    const Eigen::Vector3d axis(r[0], r[1], r[2]);
    if (axis.norm() < 1e-12 || std::fabs(r[3]) < 1e-15) {
      *q = Eigen::Quaterniond::Identity();
    } else {
      *q = Eigen::Quaterniond(Eigen::AngleAxisd(r[3], axis.normalized()));
    }
    return true;
  }

  // T(translation) T(center) R(rotation) T(-center); scale must be 1
  bool TransformPose(const Node& n, Pose* pose) {
    double t[3] = {0, 0, 0}, c[3] = {0, 0, 0}, s[3] = {1, 1, 1};
    if (!Vec(n, "translation", 3, t) || !Vec(n, "center", 3, c) || !Vec(n, "scale", 3, s))
      return false;
    for (double x : s) {
      if (std::fabs(x - 1) > 1e-9)
        return Fail(n.Field("scale")->at, n.type + ".scale other than 1 1 1 is not supported: "
                                                   "scale the geometry itself");
    }
    if (!Rotation(n, "rotation", &pose->q)) return false;
    const Eigen::Vector3d center(c[0], c[1], c[2]);
    if (n.Field("translation") &&
        !Plausible(n.Field("translation")->at, "distance", Eigen::Vector3d(t[0], t[1], t[2]).norm(),
                   n.type + ".translation (its length)"))
      return false;
    pose->p = Eigen::Vector3d(t[0], t[1], t[2]) + center - pose->q * center;
    return true;
  }

  bool Count(const Node& n) {
    if (++elements_ > kMaxElements)
      return Fail(n.at, "the scene expands to more than " + std::to_string(kMaxElements) +
                            " bodies, geoms and sites (DEF/USE repeated too often?)");
    return true;
  }

  bool Object(const Node& joint, const Pose& pose, const std::string& name) {
    vrml::Object o;
    o.name = CleanName(name.empty() ? "object" + std::to_string(model_->objects.size()) : name);
    o.file = file_;
    o.root = std::make_unique<Body>();
    if (!JointBody(joint, pose, o.root.get(), 0)) return false;
    model_->objects.push_back(std::move(o));
    return true;
  }

  // a Joint: a body with its joint, then its children
  bool JointBody(const Node& n, const Pose& pose_in_parent, Body* body, int depth) {
    if (!Count(n)) return false;
    Pose own;
    if (!TransformPose(n, &own)) return false;
    body->pose = Compose(pose_in_parent, own);
    body->name = !n.def_name.empty() ? n.def_name : n.String("name", "");
    if (body->name.empty()) body->name = "link" + std::to_string(elements_);
    body->name = CleanName(body->name);
    Joint& j = body->joint;
    j.name = body->name;
    j.at = n.at;
    const std::string type = n.String("jointType", "");
    if (type == "free") {
      j.type = Joint::kFree;
    } else if (type == "rotate" || type == "slide") {
      j.type = type == "rotate" ? Joint::kHinge : Joint::kSlide;
      if (!Axis(n, &j.axis)) return false;
      const double id = n.Number("jointId", -1);
      j.id = id >= 0 && id < 1e6 ? static_cast<int>(id) : -1;
      const Value* lo = n.Field("llimit");
      const Value* hi = n.Field("ulimit");
      if (lo && hi && lo->kind == Value::kNumbers && hi->kind == Value::kNumbers &&
          !lo->numbers.empty() && !hi->numbers.empty()) {
        j.has_range = true;
        j.lower = lo->numbers[0];
        j.upper = hi->numbers[0];
        if (!(j.lower < j.upper))
          return Fail(lo->at, "llimit " + std::to_string(j.lower) + " is not below ulimit " +
                                  std::to_string(j.upper) + " of Joint " + j.name);
        // a hinge's limits are angles, a slide's positions along its axis
        const char* quantity = j.type == Joint::kHinge ? "angle" : "height";
        if (!Plausible(lo->at, quantity, j.lower, "llimit of Joint " + j.name) ||
            !Plausible(hi->at, quantity, j.upper, "ulimit of Joint " + j.name))
          return false;
      }
      const double gear = n.Number("gearRatio", 1.0);
      j.armature = n.Number("rotorInertia", 0.0) * gear * gear;
      j.stiffness = n.Number("stiffness", 0.0);
      if (j.armature < 0 || j.stiffness < 0)
        return Fail(n.at, "Joint " + j.name + ": rotorInertia and stiffness must not be negative");
      if (!Plausible(n.at, "kp", j.stiffness, "stiffness of Joint " + j.name)) return false;
    } else if (type != "fixed" && !type.empty()) {
      return Fail(n.Field("jointType")->at, "jointType \"" + type + "\" of Joint " + j.name +
                                                " is not one of free, rotate, slide, fixed");
    }
    for (const NodePtr& c : n.Nodes("children"))
      if (!Visit(*c, Pose{}, body, depth + 1)) return false;
    return true;
  }

  // jointAxis: three numbers, or "X" / "Y" / "Z" (older files)
  bool Axis(const Node& n, Eigen::Vector3d* axis) {
    const Value* v = n.Field("jointAxis");
    if (!v) return true;
    if (v->kind == Value::kStrings && !v->strings.empty()) {
      const std::string& s = v->strings[0];
      if (s == "X" || s == "x") *axis = Eigen::Vector3d::UnitX();
      else if (s == "Y" || s == "y") *axis = Eigen::Vector3d::UnitY();
      else if (s == "Z" || s == "z") *axis = Eigen::Vector3d::UnitZ();
      else return Fail(v->at, "jointAxis \"" + s + "\" is not X, Y, Z or three numbers");
      return true;
    }
    double a[3];
    if (!Vec(n, "jointAxis", 3, a)) return false;
    *axis = Eigen::Vector3d(a[0], a[1], a[2]);
    if (!(axis->norm() > 1e-9) || !axis->allFinite())
      return Fail(v->at, "jointAxis of Joint " + n.def_name + " is zero");
    axis->normalize();
    return true;
  }

  // any node below a Joint; `pose` is the frame of the node's parent in `body`
  bool Visit(const Node& n, const Pose& pose, Body* body, int depth) {
    if (depth > kMaxVisitDepth || ++visits_ > kMaxVisits)
      return Fail(n.at, "the scene nests or repeats nodes too much (DEF/USE chains?)");
    const std::string& t = n.type;
    if (t == "Joint") {
      auto child = std::make_unique<Body>();
      if (!JointBody(n, pose, child.get(), depth)) return false;
      body->children.push_back(std::move(child));
      return true;
    }
    if (t == "Segment") return SegmentOf(n, pose, body, depth);
    if (t == "Transform" || t == "Group" || t == "Collision" || t == "Anchor" || t == "Billboard") {
      Pose p = pose;
      if (t == "Transform") {
        Pose own;
        if (!TransformPose(n, &own)) return false;
        p = Compose(pose, own);
      }
      for (const NodePtr& c : n.Nodes("children"))
        if (!Visit(*c, p, body, depth + 1)) return false;
      return true;
    }
    if (t == "Shape") return ShapeOf(n, pose, body);
    if (t == "ForceSensor" || t == "Gyro" || t == "AccelerationSensor") {
      if (!Count(n)) return false;
      Site s;
      s.kind = t == "ForceSensor" ? Site::kForce : t == "Gyro" ? Site::kGyro : Site::kAccel;
      s.name = CleanName(n.def_name.empty() ? n.String("name", t) : n.def_name);
      s.sensor_id = static_cast<int>(std::fmax(-1, std::fmin(1e6, n.Number("sensorId", -1))));
      Pose own;
      if (!TransformPose(n, &own)) return false;
      s.pose = Compose(pose, own);
      body->sites.push_back(s);
      return true;
    }
    if (t == "VisionSensor") {
      if (!Count(n)) return false;
      Camera c;
      c.name = n.String("name", "");
      if (c.name.empty()) c.name = n.def_name.empty() ? "camera" : n.def_name;
      c.name = CleanName(c.name);
      c.fov = n.Number("fieldOfView", 0.785398);
      c.sensor_id = static_cast<int>(std::fmax(-1, std::fmin(1e6, n.Number("sensorId", -1))));
      Pose own;
      if (!TransformPose(n, &own)) return false;
      c.pose = Compose(pose, own);
      body->cameras.push_back(c);
      for (const NodePtr& ch : n.Nodes("children"))
        if (!Visit(*ch, c.pose, body, depth + 1)) return false;
      return true;
    }
    // lights, viewpoints, sensors the segment does not carry: nothing to simulate
    return true;
  }

  // a Segment: mass, CoM and the inertia about the CoM in the segment's frame
  bool SegmentOf(const Node& n, const Pose& pose, Body* body, int depth) {
    const std::string label = n.def_name.empty() ? "Segment" : "Segment " + n.def_name;
    Segment s;
    s.name = n.def_name;
    s.mass = n.Number("mass", 0.0);
    double c[3] = {0, 0, 0};
    if (!Vec(n, "centerOfMass", 3, c)) return false;
    const Value* iv = n.Field("momentsOfInertia");
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
    if (iv) {
      if (iv->kind != Value::kNumbers || iv->numbers.size() != 9)
        return Fail(iv->at, "momentsOfInertia of " + label +
                                " needs 9 numbers (the 3x3 tensor about the centre of mass)");
      for (int k = 0; k < 9; ++k) inertia(k / 3, k % 3) = iv->numbers[k];
    }
    if (!(s.mass >= 0) || !std::isfinite(s.mass))
      return Fail(n.at, label + " has a negative mass");
    // 0: a segment without mass (a frame); any other mass a plausible one
    if (s.mass > 0 && !Plausible(n.at, "mass", s.mass, "mass of " + label)) return false;
    // a tensor given must be one: symmetric, eigenvalues not negative
    if (!inertia.isZero(0.0)) {
      const double scale = inertia.cwiseAbs().maxCoeff();
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(inertia);
      if (!inertia.isApprox(inertia.transpose(), 1e-9) || eig.eigenvalues().minCoeff() < -1e-12 * scale)
        return Fail(iv->at, "momentsOfInertia of " + label +
                                " is not an inertia tensor (symmetric, no negative eigenvalue)");
    }
    const Eigen::Matrix3d R = pose.q.toRotationMatrix();
    s.com = pose.p + pose.q * Eigen::Vector3d(c[0], c[1], c[2]);
    s.inertia = R * inertia * R.transpose();
    body->segments.push_back(s);
    for (const NodePtr& ch : n.Nodes("children"))
      if (!Visit(*ch, pose, body, depth + 1)) return false;
    return true;
  }

  // a Shape: Box, Cylinder, Sphere or IndexedFaceSet, with the diffuse colour of its material
  bool ShapeOf(const Node& n, const Pose& pose, Body* body) {
    const auto& geometry = n.Nodes("geometry");
    if (geometry.empty()) return true;
    if (!Count(n)) return false;
    const Node& g = *geometry[0];
    Geom geom;
    geom.pose = pose;
    if (g.type == "Box") {
      double s[3] = {2, 2, 2};
      if (!Vec(g, "size", 3, s)) return false;
      geom.type = Geom::kBox;
      geom.size = Eigen::Vector3d(s[0], s[1], s[2]) / 2;
    } else if (g.type == "Cylinder") {
      // VRML cylinders run along their Y, MuJoCo's along Z: a -90 deg turn about X
      geom.type = Geom::kCylinder;
      geom.size = Eigen::Vector3d(g.Number("radius", 1), g.Number("height", 2) / 2, 0);
      geom.pose.q = (pose.q * Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2,
                                                                   Eigen::Vector3d::UnitX())))
                        .normalized();
    } else if (g.type == "Sphere") {
      geom.type = Geom::kSphere;
      geom.size = Eigen::Vector3d(g.Number("radius", 1), 0, 0);
    } else if (g.type == "IndexedFaceSet") {
      if (!FaceSet(g, &geom)) return false;
      if (geom.mesh < 0) return true;
    } else {
      return true;  // Cone, Text, lines: not simulated
    }
    // every size MuJoCo reads must be positive
    const int sizes = geom.type == Geom::kBox ? 3 : geom.type == Geom::kCylinder ? 2
                      : geom.type == Geom::kSphere ? 1 : 0;
    if (!geom.size.allFinite() || (sizes > 0 && !(geom.size.head(sizes).minCoeff() > 0)))
      return Fail(g.at, g.type + " has a size that is not positive");
    for (int k = 0; k < sizes; ++k)
      if (!Plausible(g.at, "distance", geom.size[k], g.type + " size")) return false;
    for (const NodePtr& a : n.Nodes("appearance")) {
      for (const NodePtr& m : a->Nodes("material")) {
        double c[3] = {0.8, 0.8, 0.8};
        if (!Vec(*m, "diffuseColor", 3, c)) return false;
        geom.has_rgba = true;
        geom.rgba = Eigen::Vector4d(c[0], c[1], c[2], 1.0 - m->Number("transparency", 0));
      }
    }
    body->geoms.push_back(geom);
    return true;
  }

  // an IndexedFaceSet: its points and polygons (fanned into triangles) as a mesh
  bool FaceSet(const Node& g, Geom* geom) {
    const auto& coord = g.Nodes("coord");
    if (coord.empty()) return true;
    const Value* points = coord[0]->Field("point");
    const Value* index = g.Field("coordIndex");
    if (!points || !index || points->numbers.empty()) return true;
    if (points->kind != Value::kNumbers || points->numbers.size() % 3 != 0)
      return Fail(points->at, "Coordinate.point needs x y z triples");
    Mesh mesh;
    mesh.vertices = points->numbers;
    const int count = static_cast<int>(mesh.vertices.size() / 3);
    std::vector<int> polygon;
    auto flush = [&]() {
      for (size_t k = 2; k < polygon.size(); ++k) {
        mesh.faces.push_back(polygon[0]);
        mesh.faces.push_back(polygon[k - 1]);
        mesh.faces.push_back(polygon[k]);
      }
      polygon.clear();
    };
    for (double x : index->numbers) {
      if (x == -1) {
        flush();
        continue;
      }
      if (!(x >= 0 && x < count) || x != std::floor(x))
        return Fail(index->at, "coordIndex " + std::to_string(x) + " is not a point index (0.." +
                                   std::to_string(count - 1) + ") or -1");
      polygon.push_back(static_cast<int>(x));
    }
    flush();
    if (mesh.faces.empty()) return true;
    geom->type = Geom::kMesh;
    geom->mesh = static_cast<int>(model_->meshes.size());
    model_->meshes.push_back(std::move(mesh));
    return true;
  }

  Model* model_;
  std::string* error_;
  std::string file_;
  int elements_ = 0;
  long visits_ = 0;
};

}  // namespace

bool BuildModel(const std::vector<SourceDocument>& docs, Model* model, std::string* error) {
  *model = Model{};
  Builder b(model, error);
  for (const auto& d : docs)
    if (!b.Document(d)) return false;
  return b.Finish();
}

}  // namespace ohrp::vrml
