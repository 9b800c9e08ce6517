// hw_emulator's gap between the model and the robot (see plant_gap.h).
#include "plant_gap.h"

#include <mujoco/mujoco.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "robot_model/joint_params.h"

namespace ohrp::hw::udp {
namespace {

bool ParseNumber(const std::string& s, double* out) {
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return !s.empty() && *end == 0 && std::isfinite(*out);
}

// "a,b,c" into numbers; false when one is not a finite number
bool ParseList(const std::string& s, std::vector<double>* out) {
  out->clear();
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    double x = 0;
    if (!ParseNumber(item, &x)) return false;
    out->push_back(x);
  }
  return !s.empty() && s.back() != ',';
}

// "all" or a joint's name or index into the joints it names ([first, last))
bool ParseJoint(const std::string& s, const std::vector<std::string>& names, int* first, int* last) {
  const int n = static_cast<int>(names.size());
  if (s == "all") {
    *first = 0;
    *last = n;
    return true;
  }
  for (int j = 0; j < n; ++j) {
    if (names[j] == s) {
      *first = j;
      *last = j + 1;
      return true;
    }
  }
  char* end = nullptr;
  const long j = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != 0 || j < 0 || j >= n) return false;
  *first = static_cast<int>(j);
  *last = *first + 1;
  return true;
}

// --OPTION JOINT|all=V1[,V2]: `count` non-negative (or any sign when `signed_ok`) numbers
bool ParseJointValues(const char* option, const std::vector<std::string>& specs, size_t count,
                      bool signed_ok, const char* form,
                      const std::vector<std::string>& names, PlantGap* gap, std::string* error,
                      void (*set)(JointGap*, const std::vector<double>&)) {
  for (const std::string& spec : specs) {
    const size_t eq = spec.find('=');
    int first = 0, last = 0;
    std::vector<double> v;
    bool ok = eq != std::string::npos && ParseList(spec.substr(eq + 1), &v) && v.size() == count;
    for (double x : v) ok = ok && (signed_ok || x >= 0);
    if (ok && !ParseJoint(spec.substr(0, eq), names, &first, &last)) {
      *error = std::string(option) + " " + spec + ": no joint '" + spec.substr(0, eq) +
               "' (a joint's name, an index 0.." + std::to_string(names.size() - 1) + " or all)";
      return false;
    }
    if (!ok) {
      *error = std::string(option) + " " + spec + ": expected " + form;
      return false;
    }
    for (int j = first; j < last; ++j) set(&gap->joint[j], v);
  }
  return true;
}

// "G,A" (or 2 x 3 values with `six`) of non-negative (or any, `signed_ok`) numbers
bool ParsePair(const char* option, const std::string& s, bool six, bool signed_ok, double* a,
               double* b, std::string* error) {
  if (s.empty()) return true;
  std::vector<double> v;
  bool ok = ParseList(s, &v) && (v.size() == 2 || (six && v.size() == 6));
  for (double x : v) ok = ok && (signed_ok || x >= 0);
  if (!ok) {
    *error = std::string(option) + " " + s + ": expected " +
             (six ? (std::string(option) == "--ft-bias" ? "F,T or FX,FY,FZ,TX,TY,TZ (numbers, N and N m)"
                                                        : "G,A or GX,GY,GZ,AX,AY,AZ (numbers, rad/s and m/s^2)")
                  : "two non-negative numbers separated by a comma");
    return false;
  }
  const int n = six ? 3 : 1;
  for (int k = 0; k < n; ++k) {
    a[k] = v.size() == 6 ? v[k] : v[0];
    b[k] = v.size() == 6 ? v[3 + k] : v[1];
  }
  if (six && v.size() == 2)
    for (int k = 1; k < 3; ++k) a[k] = v[0], b[k] = v[1];
  return true;
}

}  // namespace

bool ParseGap(const GapOptions& o, const std::vector<std::string>& names, double period,
              PlantGap* gap, std::string* error) {
  *gap = PlantGap{};
  gap->joint.assign(names.size(), JointGap{});
  if (!ParseJointValues("--friction", o.friction, 2, false,
                        "JOINT|all=COULOMB,VISCOUS with non-negative numbers [N m, N m s/rad], "
                        "e.g. all=0.5,0.1",
                        names, gap, error, [](JointGap* g, const std::vector<double>& v) {
                          g->coulomb = v[0];
                          g->viscous = v[1];
                        }) ||
      !ParseJointValues("--armature", o.armature, 1, false,
                        "JOINT|all=X with a non-negative number [kg m^2], e.g. all=0.01", names,
                        gap, error,
                        [](JointGap* g, const std::vector<double>& v) { g->armature = v[0]; }) ||
      !ParseJointValues("--encoder-bias", o.encoder_bias, 1, true,
                        "JOINT|all=X with a number [rad], e.g. 3=0.01", names, gap, error,
                        [](JointGap* g, const std::vector<double>& v) { g->bias = v[0]; }))
    return false;
  const double cycles = o.delay_ms * 1e-3 / period;
  gap->delay_cycles = static_cast<int>(std::lround(cycles));
  if (!(o.delay_ms >= 0 && o.delay_ms <= kMaxDelayMs) || std::fabs(cycles - gap->delay_cycles) > 1e-6) {
    std::ostringstream s;
    s << "--delay-ms " << o.delay_ms << ": expected 0.." << kMaxDelayMs
      << " ms, a whole number of board cycles (--period " << period * 1e3 << " ms)";
    *error = s.str();
    return false;
  }
  if (!(o.encoder_noise >= 0) || !std::isfinite(o.encoder_noise)) {
    *error = "--encoder-noise: expected a non-negative std [rad]";
    return false;
  }
  gap->encoder_noise = o.encoder_noise;
  return ParsePair("--imu-bias", o.imu_bias, true, true, gap->gyro_bias, gap->accel_bias, error) &&
         ParsePair("--imu-noise", o.imu_noise, false, false, &gap->gyro_noise, &gap->accel_noise,
                   error) &&
         ParsePair("--ft-noise", o.ft_noise, false, false, &gap->force_noise, &gap->torque_noise,
                   error) &&
         ParsePair("--ft-bias", o.ft_bias, true, true, gap->force_bias, gap->torque_bias, error);
}

void ApplyGapToModel(const PlantGap& gap, const std::vector<int>& dof_adr, mjModel* m,
                     mjData* data) {
  bool armature = false;
  for (size_t j = 0; j < gap.joint.size() && j < dof_adr.size(); ++j) {
    const JointGap& g = gap.joint[j];
    const int d = dof_adr[j];
    if (g.coulomb >= 0) model::SetDofFrictionloss(m, d, g.coulomb);
    if (g.viscous >= 0) m->dof_damping[d] = g.viscous;
    m->dof_armature[d] += g.armature;
    armature |= g.armature != 0;
  }
  // MuJoCo (2.2) takes the armature into the mass matrix through the model's constants
  if (armature) mj_setConst(m, data);
}

std::string DescribeGap(const PlantGap& gap) {
  std::ostringstream s;
  int friction = 0, armature = 0, bias = 0;
  for (const JointGap& g : gap.joint) {
    friction += g.coulomb >= 0 || g.viscous >= 0;
    armature += g.armature > 0;
    bias += g.bias != 0;
  }
  if (friction) s << "friction on " << friction << " joints; ";
  if (armature) s << "armature added on " << armature << " joints; ";
  if (gap.delay_cycles) s << "actuator delay " << gap.delay_cycles << " cycles; ";
  if (bias) s << "encoder bias on " << bias << " joints; ";
  if (gap.encoder_noise > 0) s << "encoder noise " << gap.encoder_noise << " rad; ";
  bool imu_bias = false;
  for (int k = 0; k < 3; ++k) imu_bias |= gap.gyro_bias[k] != 0 || gap.accel_bias[k] != 0;
  if (imu_bias) s << "IMU bias; ";
  if (gap.gyro_noise > 0 || gap.accel_noise > 0)
    s << "IMU noise " << gap.gyro_noise << " rad/s, " << gap.accel_noise << " m/s^2; ";
  bool ft_bias = false;
  for (int k = 0; k < 3; ++k) ft_bias |= gap.force_bias[k] != 0 || gap.torque_bias[k] != 0;
  if (ft_bias) s << "F/T bias; ";
  if (gap.force_noise > 0 || gap.torque_noise > 0)
    s << "F/T noise " << gap.force_noise << " N, " << gap.torque_noise << " N m; ";
  std::string text = s.str();
  return text.empty() ? "none" : text.substr(0, text.size() - 2);
}

namespace {

model::SensorParams GapSensors(const PlantGap& gap, size_t imus, size_t forces) {
  model::SensorParams p;
  for (const JointGap& g : gap.joint) {
    model::SensorParams::Encoder e;
    e.bias = g.bias;
    e.noise = gap.encoder_noise;
    p.encoders.push_back(e);
  }
  p.imus.resize(imus);
  for (model::SensorParams::Imu& u : p.imus)
    for (int k = 0; k < 3; ++k) {
      u.gyro_bias[k] = gap.gyro_bias[k], u.gyro_noise[k] = gap.gyro_noise;
      u.accel_bias[k] = gap.accel_bias[k], u.accel_noise[k] = gap.accel_noise;
    }
  p.forces.resize(forces);
  for (model::SensorParams::ForceTorque& f : p.forces)
    for (int k = 0; k < 3; ++k) {
      f.noise[k] = gap.force_noise, f.noise[3 + k] = gap.torque_noise;
      f.bias[k] = gap.force_bias[k], f.bias[3 + k] = gap.torque_bias[k];
    }
  return p;
}

model::SensorParams GapAndFile(const PlantGap& gap, size_t imus, size_t forces,
                               const model::SensorParams& file) {
  model::SensorParams p = GapSensors(gap, imus, forces);
  if (file.encoders.size() == p.encoders.size() && file.imus.size() == imus &&
      file.forces.size() == forces) {
    model::SensorParams sum = file;
    model::AddSensorParams(p, &sum);
    return sum;
  }
  return p;
}

}  // namespace

SensorGap::SensorGap(const PlantGap& gap, size_t imus, size_t forces,
                     const model::SensorParams& file, uint64_t seed)
    : model_(GapAndFile(gap, imus, forces, file), seed) {}

}  // namespace ohrp::hw::udp
