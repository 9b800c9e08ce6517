// The self-collision file: YAML out, YAML in with file:line:key messages.
#include "collision/pair_file.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace ohrp::collision {
namespace {

//---------------- writing ----------------

std::string V(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s << std::setprecision(17) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

std::string Q(const Eigen::Quaterniond& q) {
  std::ostringstream s;
  s << std::setprecision(17) << "[" << q.w() << ", " << q.x() << ", " << q.y() << ", " << q.z()
    << "]";
  return s.str();
}

std::string PairList(const RobotGeometry& r, const std::vector<LinkPair>& pairs) {
  std::string s = "[";
  for (size_t i = 0; i < pairs.size(); ++i)
    s += (i ? ", [" : "[") + r.links[pairs[i].a].name + ", " + r.links[pairs[i].b].name + "]";
  return s + "]";
}

// the `dynamics:` section (JointDynamics per joint, segment order); nothing when there is none
void WriteDynamics(const SelfCollisionFile& f, std::ostream& o) {
  if (f.dynamics.empty()) return;
  o << "dynamics:  # per joint: inertia [kg m^2], gravity torque [N m], damping, speed [rad/s]\n";
  for (size_t j = 0; j < f.dynamics.size(); ++j) {
    const JointDynamics& d = f.dynamics[j];
    o << "  - {joint: " << f.robot.joint_names[j] << ", inertia_max: " << d.inertia_max
      << ", inertia_min: " << d.inertia_min << ", gravity_max: " << d.gravity_max
      << ", damping: " << d.damping << ", velocity_max: " << d.velocity_max
      << ", inertia_free: " << d.inertia_free;
    if (!d.support_sensor.empty())
      o << ", support_sensor: " << d.support_sensor << ", support_force: " << d.support_force;
    o << "}\n";
  }
}

// the floors of the structural pairs, when the file has them
std::string StructuralFloors(const SelfCollisionFile& f) {
  if (f.structural_floor.empty()) return "";
  std::ostringstream o;
  o << std::setprecision(17) << "structural_floor: [";
  for (size_t i = 0; i < f.structural_floor.size(); ++i) o << (i ? ", " : "") << f.structural_floor[i];
  o << "]  # [m] per structural pair: the signed distance the online check keeps\n";
  return o.str();
}

// the text and its checksum line
std::string Signed(const std::string& body) { return body + ChecksumLine(body); }

//---------------- reading ----------------

// a mistake in the file: where and what
struct Bad {
  int line;
  std::string what;
};

int LineOf(const YAML::Node& n) { return n.Mark().line + 1; }

YAML::Node Need(const YAML::Node& map, const char* key) {
  const YAML::Node n = map[key];
  if (!n) throw Bad{LineOf(map), std::string(key) + ": missing"};
  return n;
}

double Num(const YAML::Node& n, const std::string& key) {
  double x = NAN;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, x) || !std::isfinite(x))
    throw Bad{LineOf(n), key + ": must be a finite number"};
  return x;
}

int Int(const YAML::Node& n, const std::string& key) {
  int x = 0;
  if (!n.IsScalar() || !YAML::convert<int>::decode(n, x)) throw Bad{LineOf(n), key + ": must be an integer"};
  return x;
}

bool Bool(const YAML::Node& n, const std::string& key) {
  bool x = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, x)) throw Bad{LineOf(n), key + ": must be true or false"};
  return x;
}

std::string Str(const YAML::Node& n, const std::string& key) {
  if (!n.IsScalar()) throw Bad{LineOf(n), key + ": must be a single value"};
  return n.Scalar();
}

Eigen::Vector3d Vec(const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3) throw Bad{LineOf(n), key + ": must be a list of 3 numbers"};
  return {Num(n[0], key), Num(n[1], key), Num(n[2], key)};
}

Eigen::Quaterniond Quat(const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence() || n.size() != 4)
    throw Bad{LineOf(n), key + ": must be a list of 4 numbers (w, x, y, z)"};
  return Eigen::Quaterniond(Num(n[0], key), Num(n[1], key), Num(n[2], key), Num(n[3], key));
}

int JointId(const RobotGeometry& r, const YAML::Node& n, const std::string& key) {
  const std::string name = Str(n, key);
  const int j = FindJoint(r, name);
  if (j < 0) throw Bad{LineOf(n), key + ": no joint '" + name + "' in joints: or passive_joints:"};
  return j;
}

std::vector<LinkPair> Pairs(const RobotGeometry& r, const YAML::Node& n, const std::string& key) {
  if (!n.IsSequence()) throw Bad{LineOf(n), key + ": must be a list of [link, link] pairs"};
  std::vector<LinkPair> out;
  for (const auto& p : n) {
    if (!p.IsSequence() || p.size() != 2) throw Bad{LineOf(p), key + ": each pair is [link, link]"};
    int ab[2];
    for (int k = 0; k < 2; ++k) {
      ab[k] = FindLink(r, Str(p[k], key));
      if (ab[k] < 0) throw Bad{LineOf(p[k]), key + ": no link '" + p[k].Scalar() + "' in links:"};
    }
    if (ab[0] == ab[1]) throw Bad{LineOf(p), key + ": a pair of one link with itself"};
    out.push_back({std::min(ab[0], ab[1]), std::max(ab[0], ab[1])});
  }
  return out;
}

Shape ReadShape(const YAML::Node& n) {
  Shape s;
  const std::string type = Str(Need(n, "type"), "type");
  if (!ParseShape(type, &s.type))
    throw Bad{LineOf(n), "type: '" + type +
                             "' is not box, sphere, capsule, cylinder, ellipsoid or convex"};
  if (s.type != ShapeType::kConvex) s.size = Vec(Need(n, "size"), "size");
  s.p_LS = Vec(Need(n, "pos"), "pos");
  s.q_LS = Quat(Need(n, "quat"), "quat");
  if (s.type == ShapeType::kConvex) {
    for (const auto& v : Need(n, "vertices")) s.vertices.push_back(Vec(v, "vertices"));
    for (const auto& f : Need(n, "faces")) s.faces.push_back(Int(f, "faces"));
  }
  return s;
}

void ReadRobot(const YAML::Node& root, RobotGeometry* r) {
  r->name = Str(Need(root, "robot"), "robot");
  const std::string hash = Str(Need(root, "model_hash"), "model_hash");
  try {
    r->model_hash = std::stoull(hash, nullptr, 16);
  } catch (const std::exception&) {
    throw Bad{LineOf(root["model_hash"]), "model_hash: must be a hexadecimal number"};
  }
  for (const auto& j : Need(root, "joints")) {
    r->joint_names.push_back(Str(Need(j, "name"), "name"));
    r->q_min.push_back(Num(Need(j, "min"), "min"));
    r->q_max.push_back(Num(Need(j, "max"), "max"));
  }
  // passive joints (optional): joint ids after the actuated ones
  if (const YAML::Node passive = root["passive_joints"]) {
    for (const auto& j : passive) {
      r->passive_names.push_back(Str(Need(j, "name"), "name"));
      r->q_min.push_back(Num(Need(j, "min"), "min"));
      r->q_max.push_back(Num(Need(j, "max"), "max"));
    }
  }
  if (const YAML::Node unchecked = root["unchecked"])
    for (const auto& u : unchecked) r->unchecked.push_back(Str(u, "unchecked"));
  for (const auto& l : Need(root, "links")) {
    Link link;
    link.name = Str(Need(l, "name"), "name");
    link.parent = Int(Need(l, "parent"), "parent");
    link.p_PL = Vec(Need(l, "pos"), "pos");
    link.q_PL = Quat(Need(l, "quat"), "quat");
    const YAML::Node j = Need(l, "joint");
    link.joint = j.IsScalar() && j.Scalar() == "-1" ? -1 : JointId(*r, j, "joint");
    link.axis_L = Vec(Need(l, "axis"), "axis");
    link.anchor_L = Vec(Need(l, "anchor"), "anchor");
    if (const YAML::Node sl = l["slide"]) link.slide = Bool(sl, "slide");
    if (const YAML::Node jo = l["joint_only"]) link.joint_only = Bool(jo, "joint_only");
    for (const auto& s : Need(l, "shapes")) link.shapes.push_back(ReadShape(s));
    r->links.push_back(std::move(link));
  }
  const std::string problem = Validate(*r);
  if (!problem.empty()) throw Bad{LineOf(root["links"]), "links: " + problem};
}

// the optional `dynamics:` section: one entry per joint, in the joints' order
void ReadDynamics(const YAML::Node& root, SelfCollisionFile* f) {
  const YAML::Node n = root["dynamics"];
  if (!n) return;
  const RobotGeometry& r = f->robot;
  if (!n.IsSequence() || n.size() != r.joint_names.size())
    throw Bad{LineOf(n), "dynamics: must list every joint once, in the joints' order (" +
                             std::to_string(r.joint_names.size()) + " entries)"};
  for (size_t j = 0; j < n.size(); ++j) {
    const YAML::Node e = n[j];
    if (JointId(r, Need(e, "joint"), "joint") != static_cast<int>(j))
      throw Bad{LineOf(e), "dynamics: entry " + std::to_string(j) + " must be joint " + r.joint_names[j]};
    JointDynamics d;
    d.inertia_max = Num(Need(e, "inertia_max"), "inertia_max");
    d.inertia_min = Num(Need(e, "inertia_min"), "inertia_min");
    d.gravity_max = Num(Need(e, "gravity_max"), "gravity_max");
    d.damping = Num(Need(e, "damping"), "damping");
    d.velocity_max = Num(Need(e, "velocity_max"), "velocity_max");
    d.inertia_free = e["inertia_free"] ? Num(e["inertia_free"], "inertia_free") : d.inertia_max;
    if (e["support_sensor"]) {
      d.support_sensor = Str(e["support_sensor"], "support_sensor");
      d.support_force = Num(Need(e, "support_force"), "support_force");
    }
    if (!(d.inertia_min > 0 && d.inertia_min <= d.inertia_free && d.inertia_free <= d.inertia_max))
      throw Bad{LineOf(e), "dynamics: needs 0 < inertia_min <= inertia_free <= inertia_max [kg m^2]"};
    if (d.gravity_max < 0 || d.damping < 0 || d.velocity_max < 0)
      throw Bad{LineOf(e), "dynamics: gravity_max, damping and velocity_max must be >= 0"};
    f->dynamics.push_back(d);
  }
}

// the whole text of a file; false when it cannot be read
bool ReadText(const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::stringstream s;
  s << in.rdbuf();
  *text = s.str();
  return !in.bad();
}

void ReadFloors(const YAML::Node& root, SelfCollisionFile* file) {
  const YAML::Node n = root["structural_floor"];
  if (!n) return;
  if (!n.IsSequence()) throw Bad{LineOf(n), "structural_floor: must be a list of numbers [m]"};
  for (const auto& x : n) file->structural_floor.push_back(Num(x, "structural_floor"));
}

// the lists' consistency (ValidateSelfCollisionFile), then the checksum of the text
void CheckFile(const YAML::Node& root, const std::string& text, const SelfCollisionFile& file) {
  FileProblem problem;
  if (!ValidateSelfCollisionFile(file, &problem)) {
    const YAML::Node list = root[problem.key];
    int line = list ? LineOf(list) : 1;
    if (list && list.IsSequence() && problem.item >= 0 &&
        static_cast<size_t>(problem.item) < list.size())
      line = LineOf(list[problem.item]);
    throw Bad{line, problem.key + ": " + problem.what};
  }
  int line = 1;
  std::string what;
  if (!ChecksumMatches(text, &line, &what)) throw Bad{line, what};
}

}  // namespace

std::string SelfCollisionYaml(const SelfCollisionFile& f) {
  const RobotGeometry& r = f.robot;
  std::ostringstream o;
  o << std::setprecision(17);
  o << "# written by ohrp_selfcollision: do not edit, regenerate (docs/selfcollision.md)\n";
  o << "robot: " << r.name << "\n";
  o << "model_hash: \"0x" << std::hex << r.model_hash << std::dec << "\"\n";
  o << "margin: " << f.margin << "  # [m]\n";
  o << "joints:\n";
  for (size_t i = 0; i < r.joint_names.size(); ++i)
    o << "  - {name: " << r.joint_names[i] << ", min: " << r.q_min[i] << ", max: " << r.q_max[i]
      << "}\n";
  const size_t na = r.joint_names.size();
  if (!r.passive_names.empty()) {
    o << "passive_joints:  # no actuator: read from the segment's passive_q, never commanded\n";
    for (size_t k = 0; k < r.passive_names.size(); ++k)
      o << "  - {name: " << r.passive_names[k] << ", min: " << r.q_min[na + k]
        << ", max: " << r.q_max[na + k] << "}\n";
  }
  if (!r.unchecked.empty()) {
    o << "unchecked:  # parts of the robot left out of the geometry: never checked\n";
    for (const std::string& u : r.unchecked) {
      std::string quoted;  // a YAML double-quoted scalar: \ and " escaped
      for (char ch : u) quoted += ch == '"' || ch == '\\' ? std::string("\\") + ch : std::string(1, ch);
      o << "  - \"" << quoted << "\"\n";
    }
  }
  o << "links:\n";
  for (const Link& l : r.links) {
    o << "  - name: " << l.name << "\n    parent: " << l.parent << "\n    pos: " << V(l.p_PL)
      << "\n    quat: " << Q(l.q_PL) << "\n    joint: "
      << (l.joint < 0 ? std::string("-1") : JointName(r, l.joint)) << "\n    axis: "
      << V(l.axis_L) << "\n    anchor: " << V(l.anchor_L) << "\n";
    if (l.slide) o << "    slide: true  # the joint translates along the axis [m]\n";
    if (l.joint_only) o << "    joint_only: true  # a joint of the body below\n";
    o << "    shapes:\n";
    for (const Shape& s : l.shapes) {
      o << "      - {type: " << ShapeName(s.type) << ", size: " << V(s.size)
        << ", pos: " << V(s.p_LS) << ", quat: " << Q(s.q_LS);
      if (s.type == ShapeType::kConvex) {
        o << ",\n         vertices: [";
        for (size_t k = 0; k < s.vertices.size(); ++k) o << (k ? ", " : "") << V(s.vertices[k]);
        o << "],\n         faces: [";
        for (size_t k = 0; k < s.faces.size(); ++k) o << (k ? ", " : "") << s.faces[k];
        o << "]";
      }
      o << "}\n";
    }
  }
  o << "online: " << PairList(r, f.online) << "\n";
  o << "safe_ranges:\n";
  for (const SafeRange& s : f.ranges)
    o << "  - {joint: " << JointName(r, s.joint) << ", min: " << s.lo << ", max: " << s.hi
      << ", pairs: " << PairList(r, s.pairs) << "}\n";
  if (f.ranges.empty()) o << "  []\n";
  o << "structural: " << PairList(r, f.structural) << "\n";
  o << StructuralFloors(f);
  o << "never: " << PairList(r, f.never) << "\n";
  WriteDynamics(f, o);
  return Signed(o.str());
}

bool WriteSelfCollisionFile(const std::string& path, const SelfCollisionFile& file,
                            std::string* error) {
  std::ofstream out(path);
  out << SelfCollisionYaml(file);
  if (!out.good()) {
    *error = path + ": cannot write (does its directory exist?)";
    return false;
  }
  return true;
}

bool ReadSelfCollisionFile(const std::string& path, SelfCollisionFile* file, std::string* error) {
  *file = SelfCollisionFile();
  std::string text;
  if (!ReadText(path, &text)) {
    *error = path + ": cannot open (is the path right? the tool ohrp_selfcollision writes it)";
    return false;
  }
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) throw Bad{1, "the file must be a mapping (robot:, links:, online: ...)"};
    ReadRobot(root, &file->robot);
    file->margin = Num(Need(root, "margin"), "margin");
    if (file->margin < 0) throw Bad{LineOf(root["margin"]), "margin: must be >= 0 [m]"};
    file->online = Pairs(file->robot, Need(root, "online"), "online");
    file->structural = Pairs(file->robot, Need(root, "structural"), "structural");
    file->never = Pairs(file->robot, Need(root, "never"), "never");
    for (const auto& s : Need(root, "safe_ranges")) {
      SafeRange range;
      range.joint = JointId(file->robot, Need(s, "joint"), "joint");
      range.lo = Num(Need(s, "min"), "min");
      range.hi = Num(Need(s, "max"), "max");
      if (!(range.lo <= range.hi)) throw Bad{LineOf(s), "safe_ranges: min must not exceed max"};
      range.pairs = Pairs(file->robot, Need(s, "pairs"), "pairs");
      file->ranges.push_back(std::move(range));
    }
    ReadDynamics(root, file);
    ReadFloors(root, file);
    CheckFile(root, text, *file);
  } catch (const Bad& b) {
    *error = path + ":" + std::to_string(b.line) + ": " + b.what;
    return false;
  } catch (const YAML::BadFile&) {
    *error = path + ": cannot open (is the path right? the tool ohrp_selfcollision writes it)";
    return false;
  } catch (const YAML::Exception& e) {
    *error = path + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg;
    return false;
  }
  return true;
}

}  // namespace ohrp::collision
