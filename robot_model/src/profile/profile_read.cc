// Reading a robot profile (see robot_model/profile.h; the keys: docs/robots.md).
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <set>

#include "cli/plausible.h"
#include "robot_model/profile.h"

namespace ohrp::model {
namespace {

int LineOf(const YAML::Node& n) { return n.Mark().line + 1; }

// thrown inside the reader only, caught in ReadProfile: one error ends the reading
struct ProfileError {
  std::string text;
};

class Reader {
 public:
  explicit Reader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void Fail(const YAML::Node& at, const std::string& key, const std::string& what) const {
    throw ProfileError{file_ + ":" + std::to_string(LineOf(at)) + ": " + key + ": " + what};
  }

  // a mapping's keys checked against `known`
  void Keys(const YAML::Node& map, const std::string& key, const std::set<std::string>& known) const {
    if (!map.IsMap()) Fail(map, key, "must be a mapping");
    for (const auto& kv : map) {
      const std::string k = kv.first.as<std::string>();
      if (known.count(k)) continue;
      std::string list;
      for (const std::string& n : known) list += (list.empty() ? "" : ", ") + n;
      Fail(kv.first, key.empty() ? k : key + "." + k, "unknown key (known: " + list + ")");
    }
  }

  std::string Text(const YAML::Node& n, const std::string& key) const {
    if (!n.IsScalar() || n.Scalar().empty()) Fail(n, key, "must be a non-empty name");
    return n.Scalar();
  }

  double Number(const YAML::Node& n, const std::string& key, const char* quantity) const {
    double v = 0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) Fail(n, key, "must be a number");
    const std::string e = cli::CheckPlausible(quantity, v, key);
    if (!e.empty()) Fail(n, key, e.substr(key.size() + 1));
    return v;
  }

  template <size_t N>
  std::array<double, N> Vector(const YAML::Node& n, const std::string& key, const char* quantity) const {
    if (!n.IsSequence() || n.size() != N)
      Fail(n, key, "must be a list of " + std::to_string(N) + " numbers");
    std::array<double, N> v{};
    for (size_t i = 0; i < N; ++i) v[i] = Number(n[i], key + "[" + std::to_string(i) + "]", quantity);
    return v;
  }

  std::vector<std::string> Names(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence() || n.size() == 0) Fail(n, key, "must be a non-empty list of names");
    std::vector<std::string> v;
    for (size_t i = 0; i < n.size(); ++i) v.push_back(Text(n[i], key + "[" + std::to_string(i) + "]"));
    return v;
  }

  // "auto" / "none", or a mapping (returned true in *map)
  bool Mode(const YAML::Node& n, const std::string& key, bool* on) const {
    if (n.IsMap()) return true;
    const std::string v = n.IsScalar() ? n.Scalar() : "";
    if (v != "auto" && v != "none") Fail(n, key, "must be auto, none or a mapping");
    *on = v == "auto";
    return false;
  }

  // servo: {frequency: F, load_feedforward: true|false}: what balance and walk take by default
  void Servo(const YAML::Node& n, RobotProfile* p) const {
    if (!n.IsMap()) Fail(n, "servo", "must be a mapping: frequency (Hz), load_feedforward (true/false)");
    Keys(n, "servo", {"frequency", "load_feedforward"});
    if (n["frequency"]) {
      p->servo_frequency = Number(n["frequency"], "servo.frequency", "frequency");
      if (p->servo_frequency > 50) Fail(n["frequency"], "servo.frequency", "must be at most 50 Hz (balance's --servo-hz)");
    }
    if (n["load_feedforward"]) {
      bool v = false;
      if (!n["load_feedforward"].IsScalar() || !YAML::convert<bool>::decode(n["load_feedforward"], v))
        Fail(n["load_feedforward"], "servo.load_feedforward", "must be true or false");
      p->load_feedforward = v;
      p->load_feedforward_given = true;
    }
  }

  ProfileSite Site(const YAML::Node& n, const std::string& key) const {
    Keys(n, key, {"body", "pos"});
    ProfileSite s;
    s.line = LineOf(n);
    if (n["body"]) s.body = Text(n["body"], key + ".body");
    if (n["pos"]) s.pos = Vector<3>(n["pos"], key + ".pos", "body_offset");
    return s;
  }

  void Feet(const YAML::Node& n, RobotProfile* p) const {
    Keys(n, "feet", {"left", "right"});
    for (const char* side : {"left", "right"}) {
      const std::string key = std::string("feet.") + side;
      if (!n[side]) Fail(n, "feet", std::string("needs ") + side + " (its body, and its sole)");
      const YAML::Node f = n[side];
      Keys(f, key, {"body", "sole"});
      ProfileFoot foot;
      foot.side = side;
      foot.line = LineOf(f);
      if (!f["body"]) Fail(f, key, "needs body (the foot's body in the model)");
      foot.body = Text(f["body"], key + ".body");
      if (f["sole"] && !(f["sole"].IsScalar() && f["sole"].Scalar() == "derived")) {
        const YAML::Node s = f["sole"];
        Keys(s, key + ".sole", {"size", "centre"});
        if (!s["size"] || !s["centre"])
          Fail(s, key + ".sole", "needs size [x, y] and centre [x, y, z] (or: sole: derived)");
        foot.sole_given = true;
        foot.size = Vector<2>(s["size"], key + ".sole.size", "sole_size");
        foot.centre = Vector<3>(s["centre"], key + ".sole.centre", "body_offset");
      }
      p->feet.push_back(foot);
    }
  }

  void Stand(const YAML::Node& n, RobotProfile* p) const {
    Keys(n, "stand", {"keyframe", "joints", "height"});
    if (n["keyframe"].IsDefined() == n["joints"].IsDefined())
      Fail(n, "stand", "needs either keyframe (a keyframe's name) or joints (name: angle)");
    if (n["keyframe"]) p->stand_keyframe = Text(n["keyframe"], "stand.keyframe");
    if (n["joints"]) {
      if (!n["joints"].IsMap() || n["joints"].size() == 0)
        Fail(n["joints"], "stand.joints", "must be a mapping of joint names to positions [rad or m]");
      for (const auto& kv : n["joints"]) {
        const std::string name = kv.first.as<std::string>();
        p->stand_joints[name] = Number(kv.second, "stand.joints." + name, "angle");
      }
    }
    if (n["height"]) {
      if (!n["joints"]) Fail(n["height"], "stand.height", "goes with stand.joints");
      p->stand_height_given = true;
      p->stand_height = Number(n["height"], "stand.height", "height");
    }
  }

  void Actuators(const YAML::Node& n, RobotProfile* p) const {
    Keys(n, "actuators", {"type", "joints", "kp", "torque_limit"});
    if (!n["type"]) Fail(n, "actuators", "needs type (motor or position)");
    p->actuator_type = Text(n["type"], "actuators.type");
    if (p->actuator_type != "motor" && p->actuator_type != "position")
      Fail(n["type"], "actuators.type", "must be motor or position");
    if (n["joints"] && !(n["joints"].IsScalar() && n["joints"].Scalar() == "all"))
      p->actuator_joints = Names(n["joints"], "actuators.joints");
    if (p->actuator_type == "position") {
      if (!n["kp"]) Fail(n, "actuators", "position actuators need kp [N m/rad]");
      p->actuator_kp = Number(n["kp"], "actuators.kp", "kp");
    } else if (n["kp"]) {
      Fail(n["kp"], "actuators.kp", "goes with type: position");
    }
    if (n["torque_limit"]) p->actuator_limit = Number(n["torque_limit"], "actuators.torque_limit", "torque");
  }

  void NameLists(const YAML::Node& n, const std::string& key,
                 std::map<std::string, std::vector<std::string>>* out) const {
    if (!n.IsMap()) Fail(n, key, "must be a mapping of names to lists of joint names");
    for (const auto& kv : n) {
      const std::string name = kv.first.as<std::string>();
      (*out)[name] = Names(kv.second, key + "." + name);
    }
  }

  // a file the profile names, relative to the profile's folder; one that is not there is refused
  std::string FileBeside(const YAML::Node& n, const std::string& key,
                         const std::filesystem::path& base, const std::string& what) const {
    const std::string f = Text(n, key);
    const std::string path =
        std::filesystem::path(f).is_absolute() ? f : (base / f).lexically_normal().string();
    if (!std::filesystem::is_regular_file(path)) Fail(n, key, "no such file: " + path + " (" + what + ")");
    return path;
  }

  void Read(const YAML::Node& root, RobotProfile* p) const {
    Keys(root, "", {"model", "contact", "feet", "sole_thickness", "force_torque", "imu", "stand",
                    "chains", "groups", "walking", "base", "actuators", "servo", "contact_file",
                    "joint_file", "sensor_file", "self_collision"});
    if (!root["model"]) Fail(root, "model", "missing (the robot's MJCF, VRML or URDF file)");
    const std::string model = Text(root["model"], "model");
    const std::filesystem::path base = std::filesystem::path(file_).parent_path();
    p->model = std::filesystem::path(model).is_absolute() ? model : (base / model).lexically_normal().string();
    if (root["contact"]) {
      p->contact = Text(root["contact"], "contact");
      if (p->contact != "soft" && p->contact != "native")
        Fail(root["contact"], "contact", "must be soft or native");
    }
    if (!root["feet"]) Fail(root, "feet", "missing (left and right: the foot bodies)");
    Feet(root["feet"], p);
    if (root["sole_thickness"]) p->sole_thickness = Number(root["sole_thickness"], "sole_thickness", "sole_size");
    if (root["force_torque"] && Mode(root["force_torque"], "force_torque", &p->force_torque)) {
      Keys(root["force_torque"], "force_torque", {"left", "right"});
      for (const auto& kv : root["force_torque"]) {
        const std::string side = kv.first.as<std::string>();
        p->force_torque_sites[side] = Site(kv.second, "force_torque." + side);
      }
    }
    if (root["imu"] && Mode(root["imu"], "imu", &p->imu)) {
      p->imu_given = true;
      p->imu_site = Site(root["imu"], "imu");
    }
    if (root["stand"]) Stand(root["stand"], p);
    if (root["base"]) {
      const std::string base = Text(root["base"], "base");
      if (base != "free" && base != "as_modelled")
        Fail(root["base"], "base", "must be free (a free joint on the root body) or as_modelled");
      p->free_base = base == "free";
    }
    if (root["actuators"]) Actuators(root["actuators"], p);
    if (root["chains"]) NameLists(root["chains"], "chains", &p->chains);
    if (root["groups"]) NameLists(root["groups"], "groups", &p->groups);
    if (root["servo"]) Servo(root["servo"], p);
    if (root["contact_file"])
      p->contact_file = FileBeside(root["contact_file"], "contact_file", base,
                                   "the soles' parameters, as ohrp identify writes DIR/soles.yaml");
    if (root["joint_file"])
      p->joint_file = FileBeside(root["joint_file"], "joint_file", base,
                                 "the joints as identified, as ohrp identify --joints writes DIR/joints.yaml");
    if (root["sensor_file"])
      p->sensor_file = FileBeside(root["sensor_file"], "sensor_file", base,
                                  "the sensors as identified, as ohrp identify --sensors writes DIR/sensors.yaml");
    if (root["self_collision"])
      p->self_collision_file = FileBeside(root["self_collision"], "self_collision", base,
                                          "the self-collision file, as ohrp_selfcollision writes it");
    if (root["walking"]) {
      if (!root["walking"].IsMap()) Fail(root["walking"], "walking", "must be a mapping of limits");
      for (const auto& kv : root["walking"]) {
        const std::string name = kv.first.as<std::string>();
        double v = 0;
        if (!kv.second.IsScalar() || !YAML::convert<double>::decode(kv.second, v) || !std::isfinite(v))
          Fail(kv.second, "walking." + name, "must be a finite number");
        p->walking[name] = v;
      }
    }
  }

 private:
  std::string file_;
};

}  // namespace

bool IsProfilePath(const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  return ext == ".yaml" || ext == ".yml";
}

bool ReadProfile(const std::string& path, RobotProfile* profile, std::string* error) {
  *profile = RobotProfile{};
  profile->file = path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    *error = "cannot read robot profile '" + path + "'";
    return false;
  }
  try {
    const YAML::Node root = YAML::LoadFile(path);
    Reader(path).Read(root, profile);
  } catch (const ProfileError& e) {
    *error = e.text;
    return false;
  } catch (const YAML::ParserException& e) {
    *error = path + ":" + std::to_string(e.mark.line + 1) + ": not valid YAML: " + e.msg;
    return false;
  } catch (const YAML::Exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  return true;
}

}  // namespace ohrp::model
