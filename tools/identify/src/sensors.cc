// ohrp identify --sensors (see identify/sensors.h).
#include "identify/sensors.h"
#include "sensors_table.h"

#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

namespace ohrp::identify {
using detail::MovingAverage;
using detail::Table;
namespace {

bool ReadTable(const std::string& path, const SensorOptions& o, Table* t, std::string* error) {
  std::ifstream in(path);
  if (!in) return *error = "cannot read " + path, false;
  std::string line, cell;
  std::getline(in, line);
  {
    std::stringstream h(line);
    while (std::getline(h, cell, ',')) t->names.push_back(cell);
  }
  if (t->names.empty() || t->names[0] != "time")
    return *error = path + ": not a data log (its first column is not time)", false;
  for (const auto& n : t->names) t->col[n];
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    if (line.empty()) continue;
    std::stringstream s(line);
    std::vector<double> v;
    while (std::getline(s, cell, ',')) {
      char* end = nullptr;
      v.push_back(std::strtod(cell.c_str(), &end));
      if (cell.empty() || *end != 0) v.back() = NAN;
    }
    if (v.size() != t->names.size())
      return *error = path + ": line " + std::to_string(row) + " has " + std::to_string(v.size()) +
                      " cells, the header " + std::to_string(t->names.size()), false;
    if (!(v[0] >= o.from && v[0] <= o.to)) continue;
    for (size_t c = 0; c < v.size(); ++c) t->col[t->names[c]].push_back(v[c]);
  }
  return true;
}

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() > tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

nlohmann::json J(const Stat& e) { return {{"value", e.value}, {"se", e.se}}; }

}  // namespace

namespace detail {

std::vector<double> MovingAverage(const std::vector<double>& x, int width) {
  const size_t h = static_cast<size_t>(width / 2);
  std::vector<double> m;
  if (x.size() < 2 * h + 1) return m;
  double sum = 0;
  for (size_t k = 0; k < 2 * h + 1; ++k) sum += x[k];
  for (size_t k = h; k + h < x.size(); ++k) {
    m.push_back(sum / (2 * h + 1));
    if (k + h + 1 < x.size()) sum += x[k + h + 1] - x[k - h];
  }
  return m;
}

// refused when the channel's slow part moves more than tolerated (or than its noise explains)
bool Still(const std::string& name, const std::vector<double>& x, const Stat& noise, int width,
           double tolerance, std::string* error) {
  const double range = SlowRange(x, width);
  const double allowed = std::max(tolerance, 8 * noise.value / std::sqrt(width));
  if (std::isfinite(range) && range <= allowed) return true;
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s moves: its %d-sample moving average spans %.3g (tolerated "
                "%.3g): not a still window (--from/--to)", name.c_str(), width, range, allowed);
  *error = buf;
  return false;
}

}  // namespace detail

Stat MeanOf(const std::vector<double>& x) {
  Stat e;
  const size_t n = x.size();
  if (n == 0) return e;
  for (double v : x) e.value += v;
  e.value /= static_cast<double>(n);
  const size_t per = n / kBatches;
  if (per == 0) return e;
  double ss = 0;
  for (int b = 0; b < kBatches; ++b) {
    double m = 0;
    for (size_t k = b * per; k < (b + 1) * per; ++k) m += x[k];
    m /= static_cast<double>(per);
    ss += (m - e.value) * (m - e.value);
  }
  e.se = std::sqrt(ss / (kBatches - 1) / kBatches);
  return e;
}

Stat NoiseStd(const std::vector<double>& x, int width) {
  Stat e;
  const std::vector<double> m = MovingAverage(x, width);
  if (m.size() < 2) return e;
  const size_t h = static_cast<size_t>(width / 2);
  double ss = 0;
  for (size_t i = 0; i < m.size(); ++i) ss += (x[i + h] - m[i]) * (x[i + h] - m[i]);
  const double n = static_cast<double>(m.size());
  e.value = std::sqrt(ss / (n - 1) / (1.0 - 1.0 / (2 * h + 1)));
  e.se = e.value / std::sqrt(2 * (n - 1));
  return e;
}

double SlowRange(const std::vector<double>& x, int width) {
  const std::vector<double> m = MovingAverage(x, width);
  if (m.empty()) return NAN;
  const auto [lo, hi] = std::minmax_element(m.begin(), m.end());
  return *hi - *lo;
}

bool EstimateSensors(const std::string& path, const SensorOptions& o, SensorEstimates* out,
                     std::string* error) {
  *out = SensorEstimates{};
  Table t;
  if (!ReadTable(path, o, &t, error)) return false;
  const std::vector<double>& time = t.col["time"];
  out->samples = time.size();
  if (time.size() < static_cast<size_t>(10 * o.width) || time.size() < 200) {
    *error = path + ": " + std::to_string(time.size()) + " rows in the window (need " +
             std::to_string(std::max(200, 10 * o.width)) + ")";
    return false;
  }
  out->period = (time.back() - time.front()) / static_cast<double>(time.size() - 1);
  for (const std::string& n : t.names) {
    if (n.rfind("q_", 0) == 0 && t.Has("qref_" + n.substr(2))) out->joints.push_back(n.substr(2));
    if (EndsWith(n, "_fx")) out->forces.push_back(n.substr(0, n.size() - 3));
    if (EndsWith(n, "_gx")) out->imus.emplace_back().name = n.substr(0, n.size() - 3);
  }
  if (out->joints.empty() && out->forces.empty() && out->imus.empty()) {
    *error = path + ": no joint (q_J with qref_J), F/T (F_fx..) or IMU (I_gx..) columns";
    return false;
  }
  for (const std::string& j : out->joints) {
    const auto& q = t.col["q_" + j];
    out->encoder_noise.push_back(NoiseStd(q, o.width));
    out->joint_mean.push_back(MeanOf(q).value);
    out->joint_tau.push_back(t.Has("tau_" + j) ? MeanOf(t.col["tau_" + j]) : Stat{NAN, NAN});
    if (!detail::Still("joint " + j, q, out->encoder_noise.back(), o.width, o.joint_still, error)) return false;
    detail::MotionNoise(t, j, o, out);
  }
  for (const std::string& f : out->forces)
    for (const char* a : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"})
      out->ft_noise.push_back(NoiseStd(t.col[f + a], o.width)),
          out->ft_mean.push_back(MeanOf(t.col[f + a]));
  for (ImuEstimate& u : out->imus) {
    const char* axis = "xyz";
    double m[3];
    for (int k = 0; k < 3; ++k) {
      const auto& g = t.col[u.name + "_g" + axis[k]];
      const auto& a = t.col[u.name + "_a" + axis[k]];
      u.gyro_bias[k] = MeanOf(g), u.gyro_noise[k] = NoiseStd(g, o.width);
      u.accel_mean[k] = MeanOf(a), u.accel_noise[k] = NoiseStd(a, o.width);
      if (!detail::Still(u.name + "_g" + axis[k], g, u.gyro_noise[k], o.width, o.gyro_still, error) ||
          !detail::Still(u.name + "_a" + axis[k], a, u.accel_noise[k], o.width, o.accel_still, error))
        return false;
      m[k] = u.accel_mean[k].value;
    }
    // along gravity: |mean| - g, its error the means' projected on the direction
    const double norm = std::sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    double var = 0;
    for (int k = 0; k < 3; ++k) var += std::pow(m[k] / norm * u.accel_mean[k].se, 2);
    u.accel_bias_along_g = {norm - o.gravity, std::sqrt(var)};
    // across it: with the IMU's orientation logged (w, x, y, z; world z up), the specific force
    // a still IMU reads is R^T (0, 0, g), the third row of R
    const std::string qn = u.name + "_q";
    if (!(t.Has(qn + "w") && t.Has(qn + "x") && t.Has(qn + "y") && t.Has(qn + "z"))) continue;
    const auto &qw = t.col[qn + "w"], &qx = t.col[qn + "x"], &qy = t.col[qn + "y"], &qz = t.col[qn + "z"];
    bool unit = true;
    std::vector<double> d[3];
    for (size_t r = 0; r < qw.size() && unit; ++r) {
      const double w = qw[r], x = qx[r], y = qy[r], z = qz[r];
      unit = std::fabs(w * w + x * x + y * y + z * z - 1) < 1e-3;
      const double up[3] = {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
      for (int k = 0; k < 3; ++k)
        d[k].push_back(t.col[u.name + "_a" + axis[k]][r] - o.gravity * up[k]);
    }
    if (!unit) continue;  // not an orientation (zeros: a board without one)
    u.oriented = true;
    for (int k = 0; k < 3; ++k) u.accel_bias[k] = MeanOf(d[k]);
    if (!detail::OrientationNoise(t, o, &u, &out->warnings, error)) return false;
  }
  return true;
}

int IdentifySensors(const std::string& log, const std::string& out_dir, const SensorOptions& o,
                    const JointModel& model) {
  SensorEstimates s;
  std::string error;
  if (!EstimateSensors(log, o, &s, &error) ||
      (!model.model.empty() && (!EstimateEncoderBias(model, o.min_gravity_stiffness, &s, &error) ||
                                !EstimateForceBias(model, o.gravity, &s, &error)))) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return 2;
  }
  const char* axis = "xyz";
  nlohmann::json j{{"log", log}, {"samples", s.samples}, {"period", s.period},
                   {"window", {o.from, o.to}}, {"moving_average", o.width}};
  std::printf("%zu still rows of %.3g ms (estimate +- standard error)\n", s.samples, 1e3 * s.period);
  for (const ImuEstimate& u : s.imus) {
    nlohmann::json ju{{"name", u.name}, {"oriented", u.oriented},
                      {"accel_bias_along_gravity", J(u.accel_bias_along_g)}};
    std::printf("IMU %s        %12s %10s %12s %10s %12s %10s\n", u.name.c_str(), "gyro bias",
                "+-", "gyro noise", "+-", "accel noise", "+-");
    for (int k = 0; k < 3; ++k) {
      std::printf("  %c %22.4g %10.2g %12.4g %10.2g %12.4g %10.2g\n", axis[k], u.gyro_bias[k].value,
                  u.gyro_bias[k].se, u.gyro_noise[k].value, u.gyro_noise[k].se,
                  u.accel_noise[k].value, u.accel_noise[k].se);
      const std::string a(1, axis[k]);
      ju["gyro_bias_" + a] = J(u.gyro_bias[k]), ju["gyro_noise_" + a] = J(u.gyro_noise[k]);
      ju["accel_noise_" + a] = J(u.accel_noise[k]), ju["accel_mean_" + a] = J(u.accel_mean[k]);
      if (u.oriented) ju["accel_bias_" + a] = J(u.accel_bias[k]);
    }
    std::printf("  accelerometer bias along gravity (|mean| - %.4g): %.4g +- %.2g m/s^2\n",
                o.gravity, u.accel_bias_along_g.value, u.accel_bias_along_g.se);
    if (u.oriented)
      std::printf("  accelerometer bias (mean - R^T g, R the logged orientation): %.4g +- %.2g, "
                  "%.4g +- %.2g, %.4g +- %.2g m/s^2\n", u.accel_bias[0].value, u.accel_bias[0].se,
                  u.accel_bias[1].value, u.accel_bias[1].se, u.accel_bias[2].value, u.accel_bias[2].se);
    else
      std::printf("  accelerometer bias across gravity: not observable (no orientation logged: "
                  "indistinguishable from a tilt)\n");
    if (u.oriented) {
      std::printf("  orientation noise beyond the gyro's turn (x, y, z; pooled): %.4g +- %.2g, "
                  "%.4g +- %.2g, %.4g +- %.2g; %.4g +- %.2g rad\n", u.orientation_noise[0].value,
                  u.orientation_noise[0].se, u.orientation_noise[1].value, u.orientation_noise[1].se,
                  u.orientation_noise[2].value, u.orientation_noise[2].se,
                  u.orientation_noise_pooled.value, u.orientation_noise_pooled.se);
      ju["orientation_noise"] = J(u.orientation_noise_pooled);
      for (int k = 0; k < 3; ++k) {
        const std::string a(1, axis[k]);
        ju["orientation_noise_" + a] = J(u.orientation_noise[k]);
        ju["orientation_explained_" + a] = u.orientation_explained[k];
      }
    }
    j["imus"].push_back(ju);
  }
  const char* ft[6] = {"fx", "fy", "fz", "tx", "ty", "tz"};
  for (size_t f = 0; f < s.forces.size(); ++f) {
    std::printf("F/T %s noise:", s.forces[f].c_str());
    nlohmann::json jf{{"name", s.forces[f]}};
    for (int k = 0; k < 6; ++k) {
      const Stat& e = s.ft_noise[6 * f + k];
      std::printf(" %s %.3g+-%.1g", ft[k], e.value, e.se);
      jf[std::string("noise_") + ft[k]] = J(e);
    }
    std::printf("  [N, N m]\n");
    if (!s.ft_bias.empty()) {
      std::printf("F/T %s offset (mean - the model's static load of its subtree):", s.forces[f].c_str());
      for (int k = 0; k < 6; ++k) {
        const Stat& e = s.ft_bias[6 * f + k];
        std::printf(" %s %.4g+-%.1g", ft[k], e.value, e.se);
        jf[std::string("bias_") + ft[k]] = J(e);
        jf[std::string("static_load_") + ft[k]] = s.ft_expected[6 * f + k];
      }
      std::printf("  [N, N m]\n");
    }
    j["force_torque"].push_back(jf);
  }
  const bool biased = !s.encoder_bias.empty();
  if (!s.joints.empty())
    std::printf("%-18s %12s %10s %12s %10s %12s  (encoder noise, bias [rad]; gravity stiffness "
                "[N m/rad])\n", "joint", "noise", "+-", "bias", "+-", "stiffness");
  for (size_t k = 0; k < s.joints.size(); ++k) {
    std::printf("%-18s %12.4g %10.2g", s.joints[k].c_str(), s.encoder_noise[k].value,
                s.encoder_noise[k].se);
    nlohmann::json jj{{"joint", s.joints[k]}, {"encoder_noise", J(s.encoder_noise[k])}};
    if (biased && s.encoder_observable[k]) {
      std::printf(" %12.4g %10.2g %12.4g\n", s.encoder_bias[k].value, s.encoder_bias[k].se,
                  s.gravity_stiffness[k]);
      jj["encoder_bias"] = J(s.encoder_bias[k]);
      jj["gravity_stiffness"] = s.gravity_stiffness[k];
    } else if (biased) {
      std::printf(" %23s %12.4g\n", "not observable", s.gravity_stiffness[k]);
      jj["encoder_bias"] = "not observable: gravity stiffness below the threshold";
      jj["gravity_stiffness"] = s.gravity_stiffness[k];
    } else {
      std::printf("\n");
      jj["encoder_bias"] = "not observable from a still log";
    }
    if (!s.velocity_noise.empty()) {
      jj["velocity_noise"] = J(s.velocity_noise[k]);
      jj["velocity_explained"] = s.velocity_explained[k];
    }
    if (std::isfinite(s.torque_noise[k].value)) {
      jj["torque_noise"] = J(s.torque_noise[k]);
      jj["torque_explained"] = s.torque_explained[k];
    }
    j["joints"].push_back(jj);
  }
  if (!s.joints.empty())
    std::printf("%-18s %12s %10s %8s %12s %10s %8s  (beyond the motion; expl.: the share of the "
                "high-passed variance the motion explains)\n", "joint", "dq noise", "+-", "expl.",
                "tau noise", "+-", "expl.");
  for (size_t k = 0; k < s.joints.size(); ++k) {
    std::printf("%-18s", s.joints[k].c_str());
    if (s.velocity_noise.empty()) std::printf(" %32s", "no dq_ column (--log-dq)");
    else std::printf(" %12.4g %10.2g %8.3f", s.velocity_noise[k].value, s.velocity_noise[k].se,
                     s.velocity_explained[k]);
    std::printf(" %12.4g %10.2g %8.3f\n", s.torque_noise[k].value, s.torque_noise[k].se,
                s.torque_explained[k]);
  }
  for (const std::string& w : s.warnings) std::fprintf(stderr, "ohrp_identify: warning: %s\n", w.c_str());
  j["warnings"] = s.warnings;
  if (!s.joints.empty() && !biased)
    std::printf("(encoder bias: not observable from a still log: a held joint reads q + bias and "
                "nothing in the log tells q)\n");
  const std::string path = out_dir + "/sensors.json";
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  if (!f) {
    std::fprintf(stderr, "ohrp_identify: cannot write %s\n", path.c_str());
    return 2;
  }
  const std::string yaml = out_dir + "/sensors.yaml";
  if (!WriteSensorFile(s, log, yaml, &error)) {
    std::fprintf(stderr, "ohrp_identify: %s\n", error.c_str());
    return 2;
  }
  std::printf("(%s; %s for sim_host --sensor-file)\n", path.c_str(), yaml.c_str());
  return 0;
}

}  // namespace ohrp::identify
