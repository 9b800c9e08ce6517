// The sensors as identified, read, written, bound to a robot and applied (see sensor_params.h).
#include "robot_model/sensor_params.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace ohrp::model {
namespace {

std::string At(const std::string& path, const YAML::Node& n) {
  return path + ":" + std::to_string(n.Mark().line + 1) + ": ";
}

// `count` finite numbers (a scalar when count is 1) within [-max, max] ([0, max] for a noise)
bool ReadNumbers(const std::string& where, const YAML::Node& v, int count, double max,
                 bool noise, double* out, std::string* error) {
  const bool list = count > 1;
  if (list ? !(v.IsSequence() && static_cast<int>(v.size()) == count) : !v.IsScalar()) {
    *error = where + (list ? "wants a list of " + std::to_string(count) + " numbers" : "wants a number");
    return false;
  }
  for (int k = 0; k < count; ++k) {
    const YAML::Node n = list ? v[k] : v;
    double x = 0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, x) || !std::isfinite(x) ||
        std::fabs(x) > max || (noise && x < 0)) {
      std::ostringstream s;
      s << where << "'" << (n.IsScalar() ? n.Scalar() : std::string("(not a scalar)"))
        << "' is not a number in [" << (noise ? 0.0 : -max) << ", " << max << "]";
      *error = s.str();
      return false;
    }
    out[k] = x;
  }
  return true;
}

struct Key {
  const char* name;
  int count;
  double max;
  bool noise;
  double* out;
};

// one entry {KEY: VALUE, ...} whose keys are among `keys`
bool ReadEntry(const std::string& path, const std::string& section, const YAML::Node& name,
               const YAML::Node& entry, const std::vector<Key>& keys, std::string* error) {
  std::string known;
  for (const Key& k : keys) known += std::string(known.empty() ? "" : ", ") + k.name;
  const std::string what = section + ": " + name.Scalar() + ": ";
  if (!entry.IsMap() || entry.size() == 0) {
    *error = At(path, name) + what + "wants a mapping of " + known;
    return false;
  }
  for (const auto& kv : entry) {
    const Key* key = nullptr;
    for (const Key& k : keys) key = kv.first.Scalar() == k.name ? &k : key;
    if (!key) {
      *error = At(path, kv.first) + what + kv.first.Scalar() + ": unknown key (" + known + ")";
      return false;
    }
    if (!ReadNumbers(At(path, kv.first) + what + key->name + ": ", kv.second, key->count,
                     key->max, key->noise, key->out, error))
      return false;
  }
  return true;
}

// each entry of a section, unique by name
template <typename T, typename KeysOf>
bool ReadSection(const std::string& path, const YAML::Node& root, const char* section,
                 std::vector<T>* out, KeysOf keys_of, std::string* error) {
  const YAML::Node s = root[section];
  if (!s) return true;
  if (!s.IsMap()) return *error = At(path, s) + section + ": wants a mapping of names", false;
  std::set<std::string> seen;
  for (const auto& kv : s) {
    T t;
    if (!ReadEntry(path, section, kv.first, kv.second, keys_of(&t), error)) return false;
    if (!seen.insert(kv.first.Scalar()).second)
      return *error = At(path, kv.first) + section + ": " + kv.first.Scalar() + ": given twice", false;
    out->push_back(t);
  }
  return true;
}

void List(std::ostringstream& s, const char* key, const double* v, int n, bool* first) {
  bool zero = true;
  for (int k = 0; k < n; ++k) zero &= v[k] == 0;
  if (zero) return;
  s << (*first ? "" : ", ") << key << ": ";
  if (n > 1) s << "[";
  for (int k = 0; k < n; ++k) s << (k ? ", " : "") << v[k];
  if (n > 1) s << "]";
  *first = false;
}

void Line(std::ostringstream& s, const std::string& name, const std::ostringstream& body,
          const std::string& note) {
  s << "  " << name << ": {" << body.str() << "}";
  if (!note.empty()) s << "  # " << note;
  s << "\n";
}

template <typename T>
bool Bind(const std::vector<T>& entries, const std::vector<std::string>& names, const char* what,
          std::string T::*name_of, std::vector<T>* out, std::string* error) {
  std::map<std::string, size_t> index;
  out->assign(names.size(), T{});
  for (size_t i = 0; i < names.size(); ++i) index[names[i]] = i, (*out)[i].*name_of = names[i];
  for (const T& e : entries) {
    const auto it = index.find(e.*name_of);
    if (it == index.end()) {
      std::string have;
      for (const std::string& n : names) have += (have.empty() ? "" : ", ") + n;
      *error = std::string(what) + " " + e.*name_of + ": the robot has no such sensor (it has: " +
               (have.empty() ? "none" : have) + ")";
      return false;
    }
    (*out)[it->second] = e;
  }
  return true;
}

}  // namespace

bool ReadSensorParamsFile(const std::string& path, SensorParams* p, std::string* error) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    return *error = path + ": cannot read the sensor file", false;
  } catch (const YAML::Exception& e) {
    return *error = path + ":" + std::to_string(e.mark.line + 1) + ": not YAML: " + e.msg, false;
  }
  if (!root.IsMap() || root.size() == 0)
    return *error = path + ": wants a mapping of encoders:, imus: and/or force_torque:, e.g. "
                    "encoders: {LARM_ELBOW: {noise: 2.0e-4}}", false;
  for (const auto& kv : root) {
    const std::string k = kv.first.Scalar();
    if (k != "encoders" && k != "imus" && k != "force_torque")
      return *error = At(path, kv.first) + k + ": unknown key (encoders, imus, force_torque)", false;
  }
  SensorParams out;
  const bool ok =
      ReadSection(path, root, "encoders", &out.encoders, [&](SensorParams::Encoder* e) {
        return std::vector<Key>{{"bias", 1, kMaxEncoderBias, false, &e->bias},
                                {"noise", 1, kMaxEncoderNoise, true, &e->noise},
                                {"velocity_noise", 1, kMaxVelocityNoise, true, &e->velocity_noise},
                                {"torque_noise", 1, kMaxTorque, true, &e->torque_noise}};
      }, error) &&
      ReadSection(path, root, "imus", &out.imus, [&](SensorParams::Imu* u) {
        return std::vector<Key>{{"gyro_bias", 3, kMaxGyro, false, u->gyro_bias},
                                {"gyro_noise", 3, kMaxGyro, true, u->gyro_noise},
                                {"accel_bias", 3, kMaxAccel, false, u->accel_bias},
                                {"accel_noise", 3, kMaxAccel, true, u->accel_noise},
                                {"orientation_noise", 1, kMaxOrientationNoise, true, &u->orientation_noise}};
      }, error) &&
      ReadSection(path, root, "force_torque", &out.forces, [&](SensorParams::ForceTorque* f) {
        return std::vector<Key>{{"bias", 6, kMaxForce, false, f->bias},
                                {"noise", 6, kMaxForce, true, f->noise}};
      }, error);
  if (!ok) return false;
  // names: the keys, in the file's order
  size_t i = 0;
  for (const auto& kv : root["encoders"]) out.encoders[i++].joint = kv.first.Scalar();
  i = 0;
  for (const auto& kv : root["imus"]) out.imus[i++].name = kv.first.Scalar();
  i = 0;
  for (const auto& kv : root["force_torque"]) {
    SensorParams::ForceTorque& f = out.forces[i++];
    f.name = kv.first.Scalar();
    for (int k = 3; k < 6; ++k)
      if (std::fabs(f.bias[k]) > kMaxTorque || f.noise[k] > kMaxTorque)
        return *error = At(path, kv.first) + "force_torque: " + f.name +
                        ": a torque beyond " + std::to_string(kMaxTorque) + " N m", false;
  }
  *p = std::move(out);
  return true;
}

bool WriteSensorParamsFile(const std::string& path, const SensorParams& p,
                           const std::vector<std::string>& header, std::string* error) {
  std::ostringstream s;
  s.precision(6);
  for (const std::string& h : header) s << "# " << h << "\n";
  if (!p.encoders.empty()) s << "encoders:\n";
  for (const auto& e : p.encoders) {
    std::ostringstream b;
    b.precision(6);
    bool first = true;
    List(b, "bias", &e.bias, 1, &first);
    List(b, "noise", &e.noise, 1, &first);
    List(b, "velocity_noise", &e.velocity_noise, 1, &first);
    List(b, "torque_noise", &e.torque_noise, 1, &first);
    if (!first) Line(s, e.joint, b, e.note);
  }
  if (!p.imus.empty()) s << "imus:\n";
  for (const auto& u : p.imus) {
    std::ostringstream b;
    b.precision(6);
    bool first = true;
    List(b, "gyro_bias", u.gyro_bias, 3, &first);
    List(b, "gyro_noise", u.gyro_noise, 3, &first);
    List(b, "accel_bias", u.accel_bias, 3, &first);
    List(b, "accel_noise", u.accel_noise, 3, &first);
    List(b, "orientation_noise", &u.orientation_noise, 1, &first);
    if (!first) Line(s, u.name, b, u.note);
  }
  if (!p.forces.empty()) s << "force_torque:\n";
  for (const auto& f : p.forces) {
    std::ostringstream b;
    b.precision(6);
    bool first = true;
    List(b, "bias", f.bias, 6, &first);
    List(b, "noise", f.noise, 6, &first);
    if (!first) Line(s, f.name, b, f.note);
  }
  std::ofstream out(path);
  out << s.str();
  out.close();
  if (!out) return *error = "cannot write " + path, false;
  return true;
}

bool BindSensorParams(const SensorParams& file, const std::vector<std::string>& joints,
                      const std::vector<std::string>& imus, const std::vector<std::string>& forces,
                      SensorParams* by_index, std::string* error) {
  SensorParams out;
  if (!Bind(file.encoders, joints, "encoders: joint", &SensorParams::Encoder::joint, &out.encoders, error) ||
      !Bind(file.imus, imus, "imus:", &SensorParams::Imu::name, &out.imus, error) ||
      !Bind(file.forces, forces, "force_torque:", &SensorParams::ForceTorque::name, &out.forces, error))
    return false;
  *by_index = std::move(out);
  return true;
}

std::string DescribeSensorParams(const SensorParams& p) {
  int noise = 0, bias = 0;
  for (const auto& e : p.encoders) noise += e.noise > 0 || e.velocity_noise > 0 || e.torque_noise > 0, bias += e.bias != 0;
  std::ostringstream s;
  s << "encoders: " << noise << " with noise, " << bias << " with bias";
  auto any = [](const double* v, int n) {
    for (int k = 0; k < n; ++k)
      if (v[k] != 0) return true;
    return false;
  };
  for (const auto& u : p.imus)
    if (any(u.gyro_bias, 3) || any(u.gyro_noise, 3) || any(u.accel_bias, 3) || any(u.accel_noise, 3) ||
        u.orientation_noise > 0)
      s << "; IMU " << u.name << (any(u.gyro_bias, 3) || any(u.accel_bias, 3) ? " bias" : "")
        << (any(u.gyro_noise, 3) || any(u.accel_noise, 3) || u.orientation_noise > 0 ? " noise" : "");
  for (const auto& f : p.forces)
    if (any(f.bias, 6) || any(f.noise, 6))
      s << "; F/T " << f.name << (any(f.bias, 6) ? " bias" : "") << (any(f.noise, 6) ? " noise" : "");
  return s.str();
}

void AddSensorParams(const SensorParams& more, SensorParams* p) {
  auto add = [](double* to, const double* from, int n, bool noise) {
    for (int k = 0; k < n; ++k) to[k] = noise ? std::hypot(to[k], from[k]) : to[k] + from[k];
  };
  for (size_t j = 0; j < p->encoders.size() && j < more.encoders.size(); ++j) {
    SensorParams::Encoder& e = p->encoders[j];
    const SensorParams::Encoder& m = more.encoders[j];
    add(&e.bias, &m.bias, 1, false);
    add(&e.noise, &m.noise, 1, true);
    add(&e.velocity_noise, &m.velocity_noise, 1, true);
    add(&e.torque_noise, &m.torque_noise, 1, true);
  }
  for (size_t i = 0; i < p->imus.size() && i < more.imus.size(); ++i) {
    SensorParams::Imu& u = p->imus[i];
    const SensorParams::Imu& m = more.imus[i];
    add(u.gyro_bias, m.gyro_bias, 3, false);
    add(u.gyro_noise, m.gyro_noise, 3, true);
    add(u.accel_bias, m.accel_bias, 3, false);
    add(u.accel_noise, m.accel_noise, 3, true);
    add(&u.orientation_noise, &m.orientation_noise, 1, true);
  }
  for (size_t f = 0; f < p->forces.size() && f < more.forces.size(); ++f) {
    add(p->forces[f].bias, more.forces[f].bias, 6, false);
    add(p->forces[f].noise, more.forces[f].noise, 6, true);
  }
}

void SensorModel::Orientation(int u, double quat[4]) {
  if (u < 0 || u >= static_cast<int>(p_.imus.size()) || !(p_.imus[u].orientation_noise > 0)) return;
  const double std = p_.imus[u].orientation_noise;
  const double v[3] = {Noise(std), Noise(std), Noise(std)};
  const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  double d[4] = {1, 0, 0, 0};  // the error's rotation, w x y z
  if (angle > 0) {
    const double s = std::sin(0.5 * angle) / angle;
    d[0] = std::cos(0.5 * angle);
    for (int k = 0; k < 3; ++k) d[1 + k] = s * v[k];
  }
  const double* a = quat;  // quat * d, normalised
  double r[4] = {a[0] * d[0] - a[1] * d[1] - a[2] * d[2] - a[3] * d[3],
                 a[0] * d[1] + a[1] * d[0] + a[2] * d[3] - a[3] * d[2],
                 a[0] * d[2] - a[1] * d[3] + a[2] * d[0] + a[3] * d[1],
                 a[0] * d[3] + a[1] * d[2] - a[2] * d[1] + a[3] * d[0]};
  const double n = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
  for (int k = 0; k < 4; ++k) quat[k] = n > 0 ? r[k] / n : quat[k];
}

void SensorModel::Imu(int u, double gyro[3], double accel[3]) {
  if (u < 0 || u >= static_cast<int>(p_.imus.size())) return;
  const SensorParams::Imu& m = p_.imus[u];
  for (int k = 0; k < 3; ++k) {
    gyro[k] += m.gyro_bias[k] + Noise(m.gyro_noise[k]);
    accel[k] += m.accel_bias[k] + Noise(m.accel_noise[k]);
  }
}

void SensorModel::ForceTorque(int f, double force[3], double torque[3]) {
  if (f < 0 || f >= static_cast<int>(p_.forces.size())) return;
  const SensorParams::ForceTorque& m = p_.forces[f];
  for (int k = 0; k < 3; ++k) {
    force[k] += m.bias[k] + Noise(m.noise[k]);
    torque[k] += m.bias[3 + k] + Noise(m.noise[3 + k]);
  }
}

void SensorModel::ToJointFrame(const double* q_min, const double* q_max,
                               shm::CommandBlock* b) const {
  for (int j = 0; j < b->njoint && j < static_cast<int>(p_.encoders.size()); ++j) {
    const double bias = p_.encoders[j].bias;
    shm::JointCommand& c = b->joint[j];
    if (bias == 0 || c.mode != shm::JointMode::kPosition) continue;
    const bool inside = c.q_ref >= q_min[j] && c.q_ref <= q_max[j];
    c.q_ref -= bias;
    if (inside) c.q_ref = std::fmin(q_max[j], std::fmax(q_min[j], c.q_ref));
  }
}

}  // namespace ohrp::model
