// MJCF text from the VRML kinematic tree. Collision: a robot whose soles the profile names
// touches the world with its soles only (as mjcf/hrp1s/hrp1s.xml); a robot without them with all
// its geoms, never itself; other free objects and static scenery with all their geoms.
#include "vrml/mjcf_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "vrml/robot_profile.h"
#include "vrml/stance.h"

namespace ohrp::vrml {
namespace {

//---------------- number formatting ----------------

std::string Num(double x) {
  if (std::fabs(x) < 1e-12) return "0";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string Vec(const double* v, int n) {
  std::string s;
  for (int k = 0; k < n; ++k) {
    if (k) s += ' ';
    s += Num(v[k]);
  }
  return s;
}

std::string PoseAttrs(const Pose& pose) {
  std::string s;
  if (pose.p.norm() > 1e-12) s += " pos=\"" + Vec(pose.p.data(), 3) + "\"";
  Eigen::Quaterniond q = pose.q;
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  if (std::fabs(q.w() - 1) > 1e-12) {
    const double wxyz[4] = {q.w(), q.x(), q.y(), q.z()};
    s += " quat=\"" + Vec(wxyz, 4) + "\"";
  }
  return s;
}

//---------------- the writer ----------------

class Writer {
 public:
  Writer(Model* model, std::string* out) : m_(*model), out_(*out) {}

  bool Write(std::string* error) {
    robot_ = nullptr;
    for (auto& o : m_.objects)
      if (o.robot) robot_ = &o;
    if (robot_ && !CollectJoints(error)) return false;
    if (robot_) NameSoles();
    Header();
    Assets();
    out_ += "  <worldbody>\n";
    out_ += "    <light name=\"sun\" directional=\"true\" pos=\"0 0 5\" dir=\"0.3 0.2 -1\"/>\n";
    for (const Geom& g : m_.world_geoms) GeomLine(g, "vrml_scenery", "    ");
    for (const auto& o : m_.objects) ObjectBodies(o);
    out_ += "  </worldbody>\n\n";
    if (robot_) {
      Contacts();
      Actuators();
      Sensors();
      if (!soles_.empty()) Keyframes();
    }
    out_ += "</mujoco>\n";
    return true;
  }

 private:
  // the robot's motor joints in jointId order; the ids must be 0..n-1, each once
  bool CollectJoints(std::string* error) {
    std::map<int, const Joint*> by_id;
    bool ok = true;
    EachBody(*robot_->root, [&](const Body& b) {
      if (b.joint.id < 0 || !ok) return;
      if (by_id.count(b.joint.id)) {
        *error = robot_->file + ":" + At(b.joint.at) + "jointId " + std::to_string(b.joint.id) +
                 " of Joint " + b.joint.name + " is also the jointId of " +
                 by_id[b.joint.id]->name + ": each motor joint needs its own id 0..n-1";
        ok = false;
        return;
      }
      by_id[b.joint.id] = &b.joint;
    });
    if (!ok) return false;
    int expect = 0;
    for (const auto& [id, j] : by_id) {
      if (id != expect) {
        *error = robot_->file + ":" + At(j->at) + "jointIds must be 0..n-1: jointId " +
                 std::to_string(expect) + " is missing (Joint " + j->name + " has " +
                 std::to_string(id) + ")";
        return false;
      }
      joints_.push_back(j);
      ++expect;
    }
    return true;
  }

  // the profile's soles, when every foot link exists and carries a Box
  void NameSoles() {
    std::vector<std::pair<Geom*, Body*>> found;
    for (const auto& [foot, sole] : Soles()) {
      Body* b = FindBody(robot_->root.get(), foot);
      double lowest = 1e300;
      Geom* g = b ? LowestBox(b, Pose{}, &lowest) : nullptr;
      if (!g) return;
      found.push_back({g, b});
    }
    for (size_t k = 0; k < found.size(); ++k) {
      found[k].first->name = Soles()[k].second;
      soles_.push_back(found[k].first);
    }
    // the bodies that carry the sole geoms (excluded from touching each other)
    EachBody(*robot_->root, [&](const Body& b) {
      for (const Geom& g : b.geoms)
        if (!g.name.empty()) sole_bodies_.push_back(b.name);
    });
  }

  void Header() {
    out_ += "<mujoco model=\"" + m_.name + "\">\n";
    out_ += "  <!-- generated in memory from OpenHRP VRML by ohrp::vrml (robot_model/src/vrml) -->\n";
    out_ += "  <compiler angle=\"radian\" inertiafromgeom=\"false\" boundmass=\"1e-6\" boundinertia=\"1e-10\"/>\n";
    out_ += "  <option timestep=\"0.001\" integrator=\"Euler\"/>\n\n";
    out_ += "  <default>\n";
    out_ += "    <default class=\"vrml_visual\">\n";
    out_ += "      <geom contype=\"0\" conaffinity=\"0\" group=\"1\"/>\n    </default>\n";
    out_ += "    <default class=\"vrml_sole\">\n";
    out_ += std::string("      <geom contype=\"1\" conaffinity=\"1\" group=\"0\" condim=\"3\" friction=\"") +
            kFriction + "\"/>\n    </default>\n";
    out_ += "    <default class=\"vrml_robot\">\n";
    out_ += std::string("      <geom contype=\"1\" conaffinity=\"0\" group=\"0\" friction=\"") +
            kFriction + "\"/>\n    </default>\n";
    out_ += "    <default class=\"vrml_scenery\">\n";
    out_ += std::string("      <geom contype=\"1\" conaffinity=\"1\" group=\"0\" friction=\"") +
            kFriction + "\"/>\n    </default>\n";
    out_ += "  </default>\n\n";
  }

  void Assets() {
    if (m_.meshes.empty()) return;
    out_ += "  <asset>\n";
    for (size_t k = 0; k < m_.meshes.size(); ++k) {
      const Mesh& mesh = m_.meshes[k];
      out_ += "    <mesh name=\"vrml_mesh" + std::to_string(k) + "\" vertex=\"" +
              Vec(mesh.vertices.data(), static_cast<int>(mesh.vertices.size())) + "\" face=\"";
      for (size_t f = 0; f < mesh.faces.size(); ++f) {
        if (f) out_ += ' ';
        out_ += std::to_string(mesh.faces[f]);
      }
      out_ += "\"/>\n";
    }
    out_ += "  </asset>\n\n";
  }

  void GeomLine(const Geom& g, const std::string& cls, const std::string& ind) {
    static const char* kTypes[] = {"box", "cylinder", "sphere", "mesh"};
    out_ += ind + "<geom";
    if (!g.name.empty()) out_ += " name=\"" + g.name + "\"";
    out_ += " class=\"" + cls + "\" type=\"" + kTypes[g.type] + "\"";
    if (g.type == Geom::kMesh) {
      out_ += " mesh=\"vrml_mesh" + std::to_string(g.mesh) + "\"";
    } else {
      const int n = g.type == Geom::kBox ? 3 : g.type == Geom::kCylinder ? 2 : 1;
      out_ += " size=\"" + Vec(g.size.data(), n) + "\"";
    }
    out_ += PoseAttrs(g.pose);
    if (g.has_rgba) out_ += " rgba=\"" + Vec(g.rgba.data(), 4) + "\"";
    out_ += "/>\n";
  }

  // static scenery (no joint anywhere) goes into the world body itself, where contact models
  // look for the environment; its geoms are named after the object
  static bool Moves(const Body& b) {
    if (b.joint.type != Joint::kNone) return true;
    for (const auto& c : b.children)
      if (Moves(*c)) return true;
    return false;
  }

  void WorldGeoms(const Body& b, const Pose& pose, const std::string& name, int* count) {
    for (Geom g : b.geoms) {
      g.pose = Compose(pose, g.pose);
      g.name = *count == 0 ? name : name + "_" + std::to_string(*count);
      ++*count;
      GeomLine(g, "vrml_scenery", "    ");
    }
    for (const auto& c : b.children) WorldGeoms(*c, Compose(pose, c->pose), name, count);
  }

  void ObjectBodies(const Object& o) {
    const bool is_robot = &o == robot_;
    if (!is_robot && !Moves(*o.root)) {
      int count = 0;
      WorldGeoms(*o.root, o.root->pose, o.name, &count);
      return;
    }
    const bool single = o.root->children.empty();
    std::string cls = "vrml_scenery";
    if (o.root->joint.type != Joint::kNone && is_robot)
      cls = soles_.empty() ? "vrml_robot" : "vrml_visual";
    else if (is_robot && !soles_.empty())
      cls = "vrml_visual";
    else if (!single && o.root->joint.type == Joint::kFree)
      cls = "vrml_robot";
    Pose root_pose = o.root->pose;
    if (is_robot && !soles_.empty() && o.root->joint.type == Joint::kFree)
      root_pose.p.z() = RootHeight({});
    BodyXml(*o.root, o, is_robot ? "" : o.name + "_", cls, root_pose, "    ");
  }

  void BodyXml(const Body& b, const Object& o, const std::string& prefix, const std::string& cls,
               const Pose& pose, const std::string& ind) {
    const bool is_robot = &o == robot_;
    out_ += ind + "<body name=\"" + prefix + b.name + "\"" + PoseAttrs(pose) + ">\n";
    const std::string in = ind + "  ";
    const Joint& j = b.joint;
    if (j.type == Joint::kFree) {
      out_ += in + "<freejoint name=\"" + (is_robot ? std::string("root") : prefix + "root") +
              "\"/>\n";
    } else if (j.type != Joint::kNone) {
      JointXml(j, prefix, in);
    }
    Inertial(b, in);
    for (const Geom& g : b.geoms) GeomLine(g, g.name.empty() ? cls : "vrml_sole", in);
    if (is_robot) SitesAndCameras(b, in);
    for (const auto& c : b.children) BodyXml(*c, o, prefix, cls, c->pose, in);
    out_ += ind + "</body>\n";
  }

  void JointXml(const Joint& j, const std::string& prefix, const std::string& in) {
    double lo = j.lower, hi = j.upper;
    if (!j.has_range) std::tie(lo, hi) = AssumedRange(j.name);
    double stiffness = 0, damping = kJointDamping;
    // a passive bush: a spring-damper about zero
    if (j.id < 0 && j.name.find("BUSH") != std::string::npos) {
      const bool linear = j.type == Joint::kSlide;
      stiffness = j.stiffness > 0 ? j.stiffness
                                  : (linear ? kBushStiffnessLinear : kBushStiffnessAngular);
      damping = linear ? kBushDampingLinear : kBushDampingAngular;
    } else if (j.stiffness > 0) {
      stiffness = j.stiffness;
    }
    out_ += in + "<joint name=\"" + prefix + j.name + "\" type=\"" +
            (j.type == Joint::kHinge ? "hinge" : "slide") + "\" axis=\"" +
            Vec(j.axis.data(), 3) + "\" limited=\"true\" range=\"" + Num(lo) + " " + Num(hi) +
            "\" armature=\"" + Num(j.armature) + "\" damping=\"" + Num(damping) + "\"";
    if (stiffness > 0) out_ += " stiffness=\"" + Num(stiffness) + "\"";
    out_ += "/>\n";
  }

  // the segments merged about their common centre of mass (parallel axes)
  void Inertial(const Body& b, const std::string& in) {
    double mass = 0;
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const Segment& s : b.segments) {
      mass += s.mass;
      c += s.mass * s.com;
    }
    if (!(mass > 0)) return;
    c /= mass;
    Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
    for (const Segment& s : b.segments) {
      const Eigen::Vector3d d = s.com - c;
      I += s.inertia + s.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
    }
    out_ += in + "<inertial pos=\"" + Vec(c.data(), 3) + "\" mass=\"" + Num(mass) + "\" ";
    const double off = std::max({std::fabs(I(0, 1)), std::fabs(I(0, 2)), std::fabs(I(1, 2))});
    if (off < 1e-12) {
      const double d[3] = {I(0, 0), I(1, 1), I(2, 2)};
      out_ += "diaginertia=\"" + Vec(d, 3) + "\"/>\n";
    } else {
      const double f[6] = {I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)};
      out_ += "fullinertia=\"" + Vec(f, 6) + "\"/>\n";
    }
  }

  // force sensor sites; one `imu` site at the first Gyro (its VRML rotation dropped: the
  // link's axes, see mjcf/hrp1s/README.md); cameras
  void SitesAndCameras(const Body& b, const std::string& in) {
    for (const Site& s : b.sites) {
      if (s.kind == Site::kForce) {
        out_ += in + "<site name=\"" + s.name + "\" size=\"0.01\"" + PoseAttrs(s.pose) + "/>\n";
        forces_.push_back(&s);
      } else if (imu_body_.empty() || imu_body_ == b.name) {
        if (imu_body_.empty()) {
          Pose p;
          p.p = s.pose.p;
          out_ += in + "<site name=\"imu\" size=\"0.01\"" + PoseAttrs(p) + "/>\n";
          imu_body_ = b.name;
        }
        imu_.push_back(&s);
      }
    }
    for (const Camera& c : b.cameras) {
      out_ += in + "<camera name=\"" + c.name + "\"" + PoseAttrs(c.pose) + " fovy=\"" +
              Num(c.fov * 180.0 / M_PI) + "\"/>\n";
    }
  }

  void Contacts() {
    if (sole_bodies_.size() < 2) return;
    out_ += "  <contact>\n";
    for (size_t i = 0; i < sole_bodies_.size(); ++i)
      for (size_t k = i + 1; k < sole_bodies_.size(); ++k)
        out_ += "    <exclude body1=\"" + sole_bodies_[i] + "\" body2=\"" + sole_bodies_[k] +
                "\"/>\n";
    out_ += "  </contact>\n\n";
  }

  // one motor per jointId, in jointId order: the platform's joint order
  void Actuators() {
    if (joints_.empty()) return;
    out_ += "  <actuator>\n";
    for (const Joint* j : joints_) {
      out_ += "    <motor name=\"" + j->name + "\" joint=\"" + j->name + "\" gear=\"1\"";
      const double tl = TorqueLimit(j->name);
      if (tl > 0) {
        out_ += " ctrllimited=\"true\" ctrlrange=\"" + Num(-tl) + " " + Num(tl) +
                "\" forcelimited=\"true\" forcerange=\"" + Num(-tl) + " " + Num(tl) + "\"";
      }
      out_ += "/>\n";
    }
    out_ += "  </actuator>\n\n";
  }

  void Sensors() {
    out_ += "  <sensor>\n";
    for (const Joint* j : joints_)
      out_ += "    <jointpos name=\"q_" + j->name + "\" joint=\"" + j->name + "\"/>\n";
    for (const Joint* j : joints_)
      out_ += "    <jointvel name=\"dq_" + j->name + "\" joint=\"" + j->name + "\"/>\n";
    for (const Joint* j : joints_)
      out_ += "    <actuatorfrc name=\"tau_" + j->name + "\" actuator=\"" + j->name + "\"/>\n";
    std::stable_sort(forces_.begin(), forces_.end(), [](const Site* a, const Site* b) {
      const int ra = ForceSensorRank(a->name), rb = ForceSensorRank(b->name);
      return ra != rb ? ra < rb : a->sensor_id < b->sensor_id;
    });
    for (const Site* s : forces_) {
      out_ += "    <force name=\"" + s->name + "_f\" site=\"" + s->name + "\"/>\n";
      out_ += "    <torque name=\"" + s->name + "_t\" site=\"" + s->name + "\"/>\n";
    }
    for (const Site* s : imu_)
      if (s->kind == Site::kGyro) out_ += "    <gyro name=\"" + s->name + "\" site=\"imu\"/>\n";
    for (const Site* s : imu_)
      if (s->kind == Site::kAccel)
        out_ += "    <accelerometer name=\"" + s->name + "\" site=\"imu\"/>\n";
    if (!imu_.empty()) out_ += "    <framequat name=\"imu_quat\" objtype=\"site\" objname=\"imu\"/>\n";
    out_ += "  </sensor>\n\n";
  }

  // root height that puts the lowest sole point on z = 0 for joint angles q
  double RootHeight(const std::map<std::string, double>& q) const {
    return -LowestNamedPoint(*robot_->root, q);
  }

  // init (all zero) and halfsit, soles on z = 0; qpos of every object in body order
  void Keyframes() {
    std::map<std::string, double> half;
    for (const Joint* j : joints_) half[j->name] = HalfSitting(j->name);
    out_ += "  <keyframe>\n";
    Key("init", {}, RootHeight({}));
    Key("halfsit", half, RootHeight(half));
    out_ += "  </keyframe>\n";
  }

  void Key(const char* name, const std::map<std::string, double>& q, double z) {
    std::vector<double> qpos;
    for (const auto& o : m_.objects) {
      EachBody(*o.root, [&](const Body& b) {
        if (b.joint.type == Joint::kFree) {
          const Pose& p = b.pose;
          qpos.insert(qpos.end(), {p.p.x(), p.p.y(), &o == robot_ ? z : p.p.z(), p.q.w(), p.q.x(),
                                   p.q.y(), p.q.z()});
        } else if (b.joint.type != Joint::kNone) {
          auto it = q.find(b.joint.name);
          qpos.push_back(&o == robot_ && it != q.end() ? it->second : 0.0);
        }
      });
    }
    out_ += std::string("    <key name=\"") + name + "\" qpos=\"" +
            Vec(qpos.data(), static_cast<int>(qpos.size())) + "\"/>\n";
  }

  Model& m_;
  std::string& out_;
  Object* robot_ = nullptr;
  std::vector<const Joint*> joints_;
  std::vector<Geom*> soles_;
  std::vector<std::string> sole_bodies_;
  std::vector<const Site*> forces_;
  std::vector<const Site*> imu_;
  std::string imu_body_;
};

}  // namespace

bool WriteMjcf(Model* model, std::string* mjcf, std::string* error) {
  mjcf->clear();
  Writer w(model, mjcf);
  return w.Write(error);
}

}  // namespace ohrp::vrml
