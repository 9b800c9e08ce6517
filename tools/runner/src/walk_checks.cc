// Checks on a walk: goal_reached and average_speed (see runner/walk_checks.h).
#include "runner/walk_checks.h"

#include <cmath>
#include <cstdio>

namespace ohrp::runner {
namespace {

std::string Fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}

CheckResult Fail(CheckResult r, const std::string& why) {
  r.passed = false;
  r.detail = why;
  return r;
}

constexpr double kDeg = M_PI / 180;  // [rad/deg]

// the base's columns x, y, qw, qx, qy, qz, or an empty vector when one is missing
std::vector<int> BaseColumns(const datalog::Table& t) {
  std::vector<int> c;
  for (const char* k : {"base_x", "base_y", "base_qw", "base_qx", "base_qy", "base_qz"}) {
    c.push_back(t.Column(k));
    if (c.back() < 0) return {};
  }
  return c;
}

}  // namespace

//---------------- base pose ----------------

double YawOf(double qw, double qx, double qy, double qz) {
  return std::atan2(2 * (qw * qz + qx * qy), qw * qw + qx * qx - qy * qy - qz * qz);
}

std::vector<double> UnwrappedYaw(const datalog::Table& log) {
  const auto c = BaseColumns(log);
  if (c.empty()) return {};
  std::vector<double> yaw(log.rows());
  for (size_t i = 0; i < yaw.size(); ++i) {
    const double y = YawOf(log.col(c[2])[i], log.col(c[3])[i], log.col(c[4])[i], log.col(c[5])[i]);
    if (i == 0) {
      yaw[i] = y;
      continue;
    }
    // the change from the previous row, taken in (-pi, pi]
    yaw[i] = yaw[i - 1] + std::remainder(y - yaw[i - 1], 2 * M_PI);
  }
  return yaw;
}

bool FinalRelativePose(const datalog::Table& log, RelativePose* out, std::string* error, double from) {
  const auto c = BaseColumns(log);
  if (c.empty() || log.rows() == 0) {
    *error = c.empty() ? "the data log has no base pose (base_x, base_y, base_q*)"
                       : "the data log has no rows";
    return false;
  }
  size_t first = 0;
  const int tc = log.Column("time");
  if (tc >= 0) {
    while (first < log.rows() && log.col(tc)[first] < from) ++first;
    if (first == log.rows()) {
      *error = "the data log ends before `from` (" + Fmt(from) + " s)";
      return false;
    }
  }
  const std::vector<double> yaw = UnwrappedYaw(log);
  const size_t last = log.rows() - 1;
  const double dx = log.col(c[0])[last] - log.col(c[0])[first];
  const double dy = log.col(c[1])[last] - log.col(c[1])[first];
  // the world displacement seen in the initial heading frame
  const double cs = std::cos(yaw[first]), sn = std::sin(yaw[first]);
  out->x = cs * dx + sn * dy;
  out->y = -sn * dx + cs * dy;
  out->yaw = yaw[last] - yaw[first];
  return true;
}

bool MeasureMotion(const datalog::Table& log, double threshold, Motion* out, std::string* error) {
  const auto c = BaseColumns(log);
  const int tc = log.Column("time");
  if (c.empty() || tc < 0 || log.rows() == 0) {
    *error = "the data log has no time or base position, or no rows";
    return false;
  }
  const auto& t = log.col(tc);
  const auto& x = log.col(c[0]);
  const auto& y = log.col(c[1]);
  const size_t last = log.rows() - 1;
  *out = Motion{};
  out->distance = std::hypot(x[last] - x[0], y[last] - y[0]);
  // the first row `threshold` from the start, then the first within it of the end
  size_t i = 0;
  while (i <= last && std::hypot(x[i] - x[0], y[i] - y[0]) < threshold) ++i;
  if (i > last) return true;
  out->started = true;
  out->start = t[i];
  while (std::hypot(x[i] - x[last], y[i] - y[last]) > threshold) ++i;  // ends at `last`
  out->end = t[i];
  return true;
}

//---------------- checks ----------------

CheckResult GoalReached(const CheckSpec& s, const datalog::Table& log) {
  CheckResult r{"goal_reached", false, 0, "m", "", ""};
  RelativePose p;
  std::string error;
  const double from = s.Number("from", 0);
  if (!FinalRelativePose(log, &p, &error, from)) return Fail(r, error);
  const double gx = s.Number("x"), gy = s.Number("y"), gyaw = s.Number("yaw_deg");
  const double tol = s.Number("tolerance"), tol_deg = s.Number("tolerance_deg");
  const double yaw_error = std::fabs(p.yaw / kDeg - gyaw);
  r.value = std::hypot(p.x - gx, p.y - gy);
  r.passed = r.value <= tol && yaw_error <= tol_deg;
  r.limit = "<= " + Fmt(tol) + " m and " + Fmt(tol_deg) + " deg from (" + Fmt(gx) + " m, " +
            Fmt(gy) + " m, " + Fmt(gyaw) + " deg)";
  r.detail = "the base ended at x " + Fmt(p.x) + " m, y " + Fmt(p.y) + " m, yaw " +
             Fmt(p.yaw / kDeg) + " deg from its pose at " + Fmt(from) + " s (that heading's frame): " +
             Fmt(r.value) + " m and " + Fmt(yaw_error) + " deg off";
  return r;
}

CheckResult AverageSpeed(const CheckSpec& s, const datalog::Table& log) {
  CheckResult r{"average_speed", false, 0, "m/s", "", ""};
  const double threshold = s.Number("threshold"), min = s.Number("min");
  r.limit = ">= " + Fmt(min) + " m/s";
  Motion m;
  std::string error;
  if (!MeasureMotion(log, threshold, &m, &error)) return Fail(r, error);
  const std::string mm = Fmt(threshold * 1e3) + " mm";
  if (!m.started) return Fail(r, "the base never went " + mm + " from its start");
  const std::string times = "moving from t=" + Fmt(m.start) + " s (" + mm +
                            " from its start) to t=" + Fmt(m.end) + " s (within " + mm +
                            " of its final position)";
  if (!(m.end > m.start))
    return Fail(r, "too little motion to time: " + Fmt(m.distance) + " m from start to end, " + times);
  r.value = m.distance / (m.end - m.start);
  r.passed = r.value >= min;
  r.detail = Fmt(m.distance) + " m from start to end in " + Fmt(m.end - m.start) + " s, " + times;
  return r;
}

}  // namespace ohrp::runner
