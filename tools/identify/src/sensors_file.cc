// ohrp identify --sensors: the estimates written as the simulator's sensor file (DIR/sensors.yaml,
// robot_model/sensor_params.h), which sim_host --sensor-file applies.
#include <cmath>
#include <cstdio>

#include "identify/sensors.h"
#include "robot_model/sensor_params.h"

namespace ohrp::identify {
namespace {

std::string Se(const char* what, const Stat* s, int n) {
  std::string out = std::string(what) + " +-";
  char buf[32];
  for (int k = 0; k < n; ++k) {
    std::snprintf(buf, sizeof(buf), "%s%.2g", k ? "," : " ", s[k].se);
    out += buf;
  }
  return out;
}

}  // namespace

model::SensorParams SensorFileOf(const SensorEstimates& s) {
  model::SensorParams p;
  // encoders: the noise (the bias is not observable from a still log: left at 0)
  for (size_t k = 0; k < s.joints.size(); ++k) {
    const bool biased = !s.encoder_bias.empty() && s.encoder_observable[k];
    model::SensorParams::Encoder e{s.joints[k], biased ? s.encoder_bias[k].value : 0.0,
                                   s.encoder_noise[k].value,
                                   (biased ? Se("bias", &s.encoder_bias[k], 1) + "; " : std::string()) +
                                       Se("noise", &s.encoder_noise[k], 1)};
    // the velocity's noise (with dq_ columns) and the torque's, each beyond the motion
    if (!s.velocity_noise.empty()) {
      e.velocity_noise = s.velocity_noise[k].value;
      e.note += "; " + Se("velocity_noise", &s.velocity_noise[k], 1);
    }
    if (k < s.torque_noise.size() && std::isfinite(s.torque_noise[k].value)) {
      e.torque_noise = s.torque_noise[k].value;
      e.note += "; " + Se("torque_noise", &s.torque_noise[k], 1);
    }
    p.encoders.push_back(e);
  }
  for (const ImuEstimate& u : s.imus) {
    model::SensorParams::Imu m;
    m.name = u.name;
    for (int k = 0; k < 3; ++k) {
      m.gyro_bias[k] = u.gyro_bias[k].value, m.gyro_noise[k] = u.gyro_noise[k].value;
      m.accel_noise[k] = u.accel_noise[k].value;
      // across gravity a bias is a tilt unless the orientation was logged: then 0
      if (u.oriented) m.accel_bias[k] = u.accel_bias[k].value;
    }
    if (u.oriented) m.orientation_noise = u.orientation_noise_pooled.value;
    m.note = Se("gyro_bias", u.gyro_bias, 3) + "; " + Se("gyro_noise", u.gyro_noise, 3) + "; " +
             (u.oriented ? Se("accel_bias", u.accel_bias, 3)
                         : std::string("accel_bias not observable (no orientation logged)")) +
             "; " + Se("accel_noise", u.accel_noise, 3) +
             (u.oriented ? "; " + Se("orientation_noise", &u.orientation_noise_pooled, 1) : std::string());
    p.imus.push_back(m);
  }
  for (size_t f = 0; f < s.forces.size(); ++f) {
    model::SensorParams::ForceTorque m;
    m.name = s.forces[f];
    for (int k = 0; k < 6; ++k) m.noise[k] = s.ft_noise[6 * f + k].value;
    if (!s.ft_bias.empty())
      for (int k = 0; k < 6; ++k) m.bias[k] = s.ft_bias[6 * f + k].value;
    m.note = Se("noise", &s.ft_noise[6 * f], 6) +
             (s.ft_bias.empty() ? std::string("; bias not identified")
                                : "; " + Se("bias", &s.ft_bias[6 * f], 6));
    p.forces.push_back(m);
  }
  return p;
}

bool WriteSensorFile(const SensorEstimates& s, const std::string& log, const std::string& path,
                     std::string* error) {
  char window[160];
  std::snprintf(window, sizeof(window), "%zu still rows of %.3g ms", s.samples, 1e3 * s.period);
  return model::WriteSensorParamsFile(
      path, SensorFileOf(s),
      {"written by ohrp identify --sensors from " + log + " (" + window + ")",
       "for sim_host --sensor-file (robot_model/sensor_params.h); the comments: standard errors",
       s.ft_bias.empty()
           ? "encoder bias: not observable from a still log (0 here); F/T bias: not identified (0)"
           : "encoder bias: against the model's gravity torque (joints without a note: not "
             "observable, 0); F/T bias: against the model's static load (the subtrees hanging free)"},
      error);
}

}  // namespace ohrp::identify
