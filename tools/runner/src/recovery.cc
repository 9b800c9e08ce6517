// Push recovery measured on the data log (see runner/recovery.h).
#include "runner/recovery.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ohrp::runner {
namespace {

constexpr double kStanceWindow = 0.2;  // [s] before stance_at, for the stance height

// column index or -1 with an error naming it
int Need(const datalog::Table& t, const std::string& name, std::string* error) {
  const int c = t.Column(name);
  if (c < 0) *error = "the data log has no column '" + name + "'";
  return c;
}

// angle between the base's z axis and the world's [deg]: R_zz = 1 - 2 (qx^2 + qy^2) / |q|^2
double TiltDeg(double qw, double qx, double qy, double qz) {
  const double n = qw * qw + qx * qx + qy * qy + qz * qz;
  const double rzz = 1 - 2 * (qx * qx + qy * qy) / std::max(n, 1e-300);
  return std::acos(std::clamp(rzz, -1.0, 1.0)) * 180 / M_PI;
}

}  // namespace

//---------------- standing ----------------

bool MeasureStanding(const datalog::Table& t, const nlohmann::json& sim, const StandingSpec& s,
                     StandingResult* out, std::string* error) {
  const int ct = Need(t, "time", error), cz = Need(t, "base_z", error);
  const int cw = Need(t, "base_qw", error), cx = Need(t, "base_qx", error);
  const int cy = Need(t, "base_qy", error), cq = Need(t, "base_qz", error);
  if (ct < 0 || cz < 0 || cw < 0 || cx < 0 || cy < 0 || cq < 0) return false;
  const auto& time = t.col(ct);
  const auto& z = t.col(cz);
  StandingResult r;

  // the stance height just before the push
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] >= s.stance_at - kStanceWindow && time[i] <= s.stance_at) {
      sum += z[i];
      ++n;
    }
  }
  if (n == 0) {
    *error = "no logged data before t=" + std::to_string(s.stance_at) + " s for the stance height";
    return false;
  }
  r.stance_height = sum / n;

  // height and tilt from `after` on
  r.lowest_height = std::numeric_limits<double>::infinity();
  size_t rows = 0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] < s.after) continue;
    ++rows;
    r.lowest_height = std::min(r.lowest_height, z[i]);
    r.largest_tilt = std::max(r.largest_tilt, TiltDeg(t.col(cw)[i], t.col(cx)[i], t.col(cy)[i], t.col(cq)[i]));
  }
  char b[256];
  if (rows == 0) {
    r.standing = false;
    std::snprintf(b, sizeof(b), "the log ends at t=%.3f s, before t=%.3f s", time.empty() ? 0.0 : time.back(), s.after);
    r.why = b;
    *out = r;
    return true;
  }
  const bool high = r.lowest_height >= s.min_height_fraction * r.stance_height;
  const bool upright = r.largest_tilt <= s.max_tilt_deg;

  // the feet carry the robot
  bool loaded = true;
  if (!s.sensors.empty()) {
    double mass = sim.value("robot_mass", 0.0);
    std::vector<int> cols;
    for (const auto& name : s.sensors) {
      const int c = Need(t, name + "_fz", error);
      if (c < 0) return false;
      cols.push_back(c);
      if (sim.contains("mass_below") && sim["mass_below"].contains(name))
        mass -= sim["mass_below"][name].get<double>();
    }
    const auto grav = sim.value("gravity", std::vector<double>{0, 0, -9.81});
    const double weight = mass * std::sqrt(grav[0] * grav[0] + grav[1] * grav[1] + grav[2] * grav[2]);
    if (!(weight > 0)) {
      *error = "the load test needs robot_mass in sim_host's summary";
      return false;
    }
    double fz = 0;
    for (size_t i = 0; i < time.size(); ++i)
      if (time[i] >= s.after)
        for (int c : cols) fz += t.col(c)[i];
    r.load_ratio = fz / rows / weight;
    loaded = std::fabs(r.load_ratio - 1) <= s.load_tolerance;
  }
  r.standing = high && upright && loaded;
  std::snprintf(b, sizeof(b),
                "from t=%.2f s: lowest base %.3f m (%.0f %% of the stance %.3f m, >= %.0f %% needed), "
                "largest tilt %.1f deg (<= %.0f)",
                s.after, r.lowest_height, 100 * r.lowest_height / r.stance_height, r.stance_height,
                100 * s.min_height_fraction, r.largest_tilt, s.max_tilt_deg);
  r.why = b;
  if (!s.sensors.empty()) {
    std::snprintf(b, sizeof(b), ", feet carry %.0f %% of the weight (within %.0f %%)",
                  100 * r.load_ratio, 100 * s.load_tolerance);
    r.why += b;
  }
  *out = r;
  return true;
}

//---------------- settling ----------------

bool MeasureSettling(const datalog::Table& t, const SettleSpec& s, SettleResult* out, std::string* error) {
  const int ct = Need(t, "time", error), cx = Need(t, "base_x", error), cy = Need(t, "base_y", error);
  if (ct < 0 || cx < 0 || cy < 0) return false;
  std::vector<int> torque_cols;
  for (const auto& name : s.sensors) {
    for (const char* axis : {"_tx", "_ty"}) {
      const int c = Need(t, name + axis, error);
      if (c < 0) return false;
      torque_cols.push_back(c);
    }
  }
  const auto& time = t.col(ct);
  const double end = s.at + s.duration;

  // the stance: means over the baseline window before the push
  std::vector<double> mean(torque_cols.size(), 0.0);
  double x0 = 0, y0 = 0;
  int n = 0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] < s.at - s.baseline || time[i] >= s.at) continue;
    x0 += t.col(cx)[i];
    y0 += t.col(cy)[i];
    for (size_t k = 0; k < torque_cols.size(); ++k) mean[k] += t.col(torque_cols[k])[i];
    ++n;
  }
  if (n == 0) {
    *error = "no logged data in the baseline window before the push at t=" + std::to_string(s.at) + " s";
    return false;
  }
  if (time.empty() || time.back() < end) {
    *error = "the log ends before the push does";
    return false;
  }
  x0 /= n;
  y0 /= n;
  for (double& m : mean) m /= n;

  // deviations from the push's start on: horizontal distance and torque norm e(t)
  std::vector<double> dist, e, tt;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] < s.at) continue;
    tt.push_back(time[i]);
    dist.push_back(std::hypot(t.col(cx)[i] - x0, t.col(cy)[i] - y0));
    double e2 = 0;
    for (size_t k = 0; k < torque_cols.size(); ++k) {
      const double dev = t.col(torque_cols[k])[i] - mean[k];
      e2 += dev * dev;
    }
    e.push_back(std::sqrt(e2));
  }
  SettleResult r;
  r.first_peak = *std::max_element(e.begin(), e.end());
  r.base_excursion = *std::max_element(dist.begin(), dist.end());

  // walking back from the log's end: the last sample outside each bound; the envelope E(t)
  // is the running maximum of e from the end
  const double inf = std::numeric_limits<double>::infinity();
  r.base_time = 0;
  r.torque_time = 0;
  bool base_found = false, torque_found = false;
  double envelope = 0;
  for (size_t j = tt.size(); j-- > 0;) {
    envelope = std::max(envelope, e[j]);
    if (!base_found && dist[j] > s.tolerance) {
      base_found = true;
      r.base_time = j + 1 < tt.size() ? std::max(0.0, tt[j + 1] - end) : inf;
    }
    if (!torque_found && envelope >= s.fraction * r.first_peak) {
      torque_found = true;
      r.torque_time = j + 1 < tt.size() ? std::max(0.0, tt[j + 1] - end) : inf;
    }
  }
  if (!(r.first_peak > 0)) r.torque_time = 0;  // no deviation at all
  r.settled = r.base_time <= s.within && r.torque_time <= s.within;
  *out = r;
  return true;
}

}  // namespace ohrp::runner
