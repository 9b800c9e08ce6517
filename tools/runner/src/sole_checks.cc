// Checks on the soles' contact: cop_inside and foot_lifted (see runner/sole_checks.h).
#include "runner/sole_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "runner/checks.h"

namespace ohrp::runner {
namespace {

std::string Fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}


bool Truthy(const std::string& v) { return v == "true" || v == "1" || v == "yes" || v == "on"; }

CheckResult Fail(CheckResult r, const std::string& why) {
  r.passed = false;
  r.detail = why;
  return r;
}

// the columns of one F/T sensor: fx fy fz tx ty tz, or an empty vector when one is missing
std::vector<int> SensorColumns(const datalog::Table& t, const std::string& name) {
  std::vector<int> c;
  for (const char* k : {"_fx", "_fy", "_fz", "_tx", "_ty", "_tz"}) {
    c.push_back(t.Column(name + k));
    if (c.back() < 0) return {};
  }
  return c;
}

}  // namespace

//---------------- centre of pressure ----------------

void GroundWrench(const double f[3], const double n[3], double mass, const double com[3],
                  double g, double f_g[3], double n_g[3]) {
  const double w = mass * g;
  f_g[0] = f[0];
  f_g[1] = f[1];
  f_g[2] = f[2] + w;
  n_g[0] = n[0] + com[1] * w;
  n_g[1] = n[1] - com[0] * w;
  n_g[2] = n[2];
}

bool CentreOfPressure(const double f[3], const double n[3], double z, double* px, double* py) {
  if (!(f[2] > 0)) return false;
  *px = (z * f[0] - n[1]) / f[2];
  *py = (n[0] + z * f[1]) / f[2];
  return true;
}

double InsideDistance(const SoleRect& r, double px, double py) {
  return std::min({px - r.x[0], r.x[1] - px, py - r.y[0], r.y[1] - py});
}

bool SoleFromSummary(const nlohmann::json& sim, const std::string& sensor, SoleRect* out,
                     std::string* error) {
  if (!sim.contains("soles") || !sim["soles"].contains(sensor)) {
    *error = "sim_host's summary has no sole under the sensor '" + sensor +
             "' (key \"soles\"; is it an ankle F/T sensor above a *_SOLE box?)";
    return false;
  }
  const auto& s = sim["soles"][sensor];
  out->x[0] = s.at("x").at(0).get<double>();
  out->x[1] = s.at("x").at(1).get<double>();
  out->y[0] = s.at("y").at(0).get<double>();
  out->y[1] = s.at("y").at(1).get<double>();
  out->z = s.at("z").get<double>();
  out->foot_mass = s.value("foot_mass", 0.0);
  if (s.contains("foot_com"))
    for (int i = 0; i < 3; ++i) out->foot_com[i] = s["foot_com"].at(i).get<double>();
  return true;
}

//---------------- cop_inside ----------------

CheckResult CopInside(const CheckSpec& s, const datalog::Table& t, const nlohmann::json& sim) {
  CheckResult r{"cop_inside", false, 0, "m", "", ""};
  const double after = s.Number("after", 0), until = s.Number("until", 1e30);
  const double margin = s.Number("margin");
  const double min_fz = s.Number("min_fz");
  const bool require_loaded = s.Has("require_loaded") && Truthy(s.params.at("require_loaded"));
  const bool foot_weight = !s.Has("foot_weight") || Truthy(s.params.at("foot_weight"));
  const auto& grav = sim.value("gravity", std::vector<double>{0, 0, -9.81});
  const double g = foot_weight ? std::sqrt(grav[0] * grav[0] + grav[1] * grav[1] + grav[2] * grav[2]) : 0;
  r.limit = ">= " + Fmt(margin) + " m inside the sole's edges (soles with fz >= " + Fmt(min_fz) + " N" +
            (foot_weight ? ", the foot's weight corrected)" : ")");

  // the sensors: the list given, or every sensor with a sole
  std::vector<std::string> sensors;
  if (s.Has("sensors")) {
    sensors = SplitList(s.params.at("sensors"));
  } else if (sim.contains("soles")) {
    for (const auto& item : sim["soles"].items()) sensors.push_back(item.key());
  }
  if (sensors.empty()) return Fail(r, "no sensor with a sole (sim_host's summary has no \"soles\")");
  std::vector<SoleRect> rects(sensors.size());
  std::vector<std::vector<int>> cols(sensors.size());
  for (size_t k = 0; k < sensors.size(); ++k) {
    std::string error;
    if (!SoleFromSummary(sim, sensors[k], &rects[k], &error)) return Fail(r, error);
    cols[k] = SensorColumns(t, sensors[k]);
    if (cols[k].empty()) return Fail(r, "the data log has no force/torque columns for '" + sensors[k] + "'");
  }

  // every row of the window, every loaded sole
  const auto& time = t.col(t.Column("time"));
  double worst = std::numeric_limits<double>::infinity(), worst_t = 0, worst_x = 0, worst_y = 0;
  std::string worst_sensor, unloaded;
  double unloaded_t = 0;
  std::vector<double> smallest(sensors.size(), std::numeric_limits<double>::infinity());
  size_t rows = 0, judged = 0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] < after || time[i] > until) continue;
    ++rows;
    for (size_t k = 0; k < sensors.size(); ++k) {
      const double f_log[3] = {t.col(cols[k][0])[i], t.col(cols[k][1])[i], t.col(cols[k][2])[i]};
      const double n_log[3] = {t.col(cols[k][3])[i], t.col(cols[k][4])[i], t.col(cols[k][5])[i]};
      double f[3], n[3], px = 0, py = 0;
      GroundWrench(f_log, n_log, rects[k].foot_mass, rects[k].foot_com, g, f, n);
      if (f[2] < min_fz || !CentreOfPressure(f, n, rects[k].z, &px, &py)) {
        if (require_loaded && unloaded.empty()) {
          unloaded = sensors[k];
          unloaded_t = time[i];
        }
        continue;  // lifted: not judged
      }
      ++judged;
      const double d = InsideDistance(rects[k], px, py);
      smallest[k] = std::min(smallest[k], d);
      if (d < worst) {
        worst = d;
        worst_t = time[i];
        worst_sensor = sensors[k];
        worst_x = px;
        worst_y = py;
      }
    }
  }
  if (rows == 0) return Fail(r, "no logged data in the window");
  if (judged == 0) return Fail(r, "no sole carried " + Fmt(min_fz) + " N or more in the window");
  r.value = worst;
  r.passed = worst >= margin && unloaded.empty();
  std::string per;
  for (size_t k = 0; k < sensors.size(); ++k)
    per += (k ? ", " : "") + sensors[k] + " " +
           (std::isfinite(smallest[k]) ? Fmt(smallest[k] * 1e3) + " mm" : "never loaded");
  r.detail = "smallest CoP distance inside the sole's edges " + Fmt(worst * 1e3) + " mm at " +
             worst_sensor + ", t=" + Fmt(worst_t) + " s (CoP " + Fmt(worst_x) + ", " +
             Fmt(worst_y) + " m in the sensor frame); per sensor: " + per;
  if (!unloaded.empty())
    r.detail = unloaded + " carried less than " + Fmt(min_fz) + " N at t=" + Fmt(unloaded_t) +
               " s (require_loaded); " + r.detail;
  return r;
}

//---------------- foot_lifted ----------------

CheckResult FootLifted(const CheckSpec& s, const datalog::Table& t) {
  CheckResult r{"foot_lifted", false, 0, "N", "", ""};
  if (!s.Has("sensor") || !s.Has("after") || !s.Has("until"))
    return Fail(r, "the check needs 'sensor', 'after' and 'until' [s]");
  const std::string sensor = s.params.at("sensor");
  r.name = "foot_lifted_" + sensor;
  const double after = s.Number("after", 0), until = s.Number("until", 0);
  const double max_fz = s.Number("max_fz");
  const int c = t.Column(sensor + "_fz");
  if (c < 0) return Fail(r, "no force sensor '" + sensor + "' in the log");
  const auto& time = t.col(t.Column("time"));
  const auto& fz = t.col(c);
  double largest = -std::numeric_limits<double>::infinity(), at = 0;
  size_t rows = 0;
  for (size_t i = 0; i < time.size(); ++i) {
    if (time[i] < after || time[i] > until) continue;
    ++rows;
    if (fz[i] > largest) {
      largest = fz[i];
      at = time[i];
    }
  }
  r.limit = "< " + Fmt(max_fz) + " N over [" + Fmt(after) + ", " + Fmt(until) + "] s";
  // a log that stops before the window ends does not show the foot in the air throughout
  if (rows == 0 || time.back() < until)
    return Fail(r, "the log ends at t=" + Fmt(time.empty() ? 0.0 : time.back()) +
                       " s, before the window's end");
  r.value = largest;
  r.passed = largest < max_fz;
  r.detail = "largest vertical force on " + sensor + " " + Fmt(largest) + " N at t=" + Fmt(at) + " s";
  return r;
}

}  // namespace ohrp::runner
