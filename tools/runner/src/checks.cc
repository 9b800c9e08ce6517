// Scenario checks (see checks.h).
#include "runner/checks.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "runner/check_keys.h"
#include "runner/recovery.h"
#include "runner/sole_checks.h"
#include "runner/vision_checks.h"
#include "runner/obstacle_checks.h"
#include "runner/walk_checks.h"

namespace ohrp::runner {

//---------------- checks ----------------
namespace {


std::string Fmt(double v) {
  char b[64];
  std::snprintf(b, sizeof(b), "%.4g", v);
  return b;
}

// rows whose time lies in [after, until]
std::vector<size_t> Window(const datalog::Table& t, double after, double until) {
  std::vector<size_t> rows;
  const auto& time = t.col(t.Column("time"));
  for (size_t i = 0; i < time.size(); ++i)
    if (time[i] >= after && time[i] <= until) rows.push_back(i);
  return rows;
}

CheckResult Fail(CheckResult r, const std::string& why) {
  r.passed = false;
  r.detail = why;
  return r;
}

CheckResult BaseHeight(const CheckSpec& s, const datalog::Table& t) {
  CheckResult r{"base_height", false, 0, "m", "", ""};
  const auto rows = Window(t, s.Number("after", 0), s.Number("until", 1e30));
  if (rows.empty()) return Fail(r, "no logged data in the window");
  const auto& z = t.col(t.Column("base_z"));
  double ref = 0;
  for (size_t i : rows) ref += z[i];
  ref /= rows.size();
  if (s.Has("reference")) ref = s.Number("reference", ref);
  double worst = 0;
  for (size_t i : rows) worst = std::max(worst, std::fabs(z[i] - ref));
  const double tol = s.Number("tolerance");
  r.value = worst;
  r.passed = worst <= tol;
  r.limit = "<= " + Fmt(tol) + " from " + Fmt(ref) + " m";
  r.detail = "largest deviation of the base height from " + Fmt(ref) + " m after t=" +
             Fmt(s.Number("after", 0)) + " s";
  return r;
}

CheckResult NotFallen(const CheckSpec& s, const datalog::Table& t) {
  CheckResult r{"not_fallen", false, 0, "m", "", ""};
  const double min_h = s.Number("min_height");
  const double max_tilt = s.Number("max_tilt_deg");
  const auto& z = t.col(t.Column("base_z"));
  const auto& qw = t.col(t.Column("base_qw"));
  const auto& qx = t.col(t.Column("base_qx"));
  const auto& qy = t.col(t.Column("base_qy"));
  const auto& qz = t.col(t.Column("base_qz"));
  double lowest = 1e30, tilt = 0;
  for (size_t i = 0; i < z.size(); ++i) {
    lowest = std::min(lowest, z[i]);
    // angle between the base's z axis and the world's: R_zz = 1 - 2 (qx^2 + qy^2) / |q|^2
    const double n = qw[i] * qw[i] + qx[i] * qx[i] + qy[i] * qy[i] + qz[i] * qz[i];
    const double rzz = 1 - 2 * (qx[i] * qx[i] + qy[i] * qy[i]) / std::max(n, 1e-300);
    tilt = std::max(tilt, std::acos(std::clamp(rzz, -1.0, 1.0)) * 180 / M_PI);
  }
  r.value = lowest;
  r.passed = !z.empty() && lowest >= min_h && tilt <= max_tilt;
  r.limit = ">= " + Fmt(min_h) + " m, tilt <= " + Fmt(max_tilt) + " deg";
  r.detail = "lowest base height " + Fmt(lowest) + " m, largest tilt " + Fmt(tilt) + " deg";
  return r;
}

CheckResult FeetCarryWeight(const CheckSpec& s, const datalog::Table& t, const nlohmann::json& sim) {
  CheckResult r{"feet_carry_weight", false, 0, "", "", ""};
  const auto sensors = SplitList(s.params.count("sensors") ? s.params.at("sensors") : "");
  if (sensors.empty()) return Fail(r, "the check needs 'sensors' (e.g. [rfsensor, lfsensor])");
  const auto rows = Window(t, s.Number("after", 0), s.Number("until", 1e30));
  if (rows.empty()) return Fail(r, "no logged data in the window");
  double mass = sim.value("robot_mass", 0.0);
  for (const auto& name : sensors) {
    if (t.Column(name + "_fz") < 0) return Fail(r, "no force sensor '" + name + "' in the log");
    if (sim.contains("mass_below") && sim["mass_below"].contains(name))
      mass -= sim["mass_below"][name].get<double>();
  }
  const auto& grav = sim.value("gravity", std::vector<double>{0, 0, -9.81});
  const double g = std::sqrt(grav[0] * grav[0] + grav[1] * grav[1] + grav[2] * grav[2]);
  double sum = 0;
  for (size_t i : rows)
    for (const auto& name : sensors) sum += t.col(t.Column(name + "_fz"))[i];
  const double mean = sum / rows.size();
  const double weight = mass * g;
  const double tol = s.Number("tolerance");
  r.value = std::fabs(mean - weight) / weight;
  r.passed = r.value <= tol;
  r.limit = "<= " + Fmt(tol) + " relative";
  r.detail = "mean sum of fz " + Fmt(mean) + " N vs weight carried " + Fmt(weight) + " N (" +
             Fmt(mass) + " kg above the sensors)";
  return r;
}

CheckResult BaseDisplacement(const CheckSpec& s, const datalog::Table& t) {
  const std::string axis = s.params.count("axis") ? s.params.at("axis") : "x";
  const double from = s.Number("from", 0);
  CheckResult r{"base_displacement_" + axis + (from > 0 ? "_after_" + Fmt(from) + "s" : ""),
                false, 0, "m", "", ""};
  const int c = t.Column("base_" + axis);
  if (c < 0) return Fail(r, "axis must be x, y or z");
  const auto rows = Window(t, from, 1e30);
  if (rows.empty()) return Fail(r, "no logged data");
  const auto& p = t.col(c);
  r.value = p[rows.back()] - p[rows.front()];
  const double lo = s.Number("min", -1e30), hi = s.Number("max", 1e30);
  r.passed = r.value >= lo && r.value <= hi;
  r.limit = "[" + (s.Has("min") ? Fmt(lo) : "-inf") + ", " + (s.Has("max") ? Fmt(hi) : "inf") + "] m";
  r.detail = "base moved " + Fmt(r.value) + " m along " + axis;
  return r;
}

// high-frequency content of a force: the RMS of the force less its moving average over
// `window`, the largest over the sensors (the ringing of a stiff contact at each impact)
CheckResult ForceRinging(const CheckSpec& s, const datalog::Table& t) {
  CheckResult r{"force_ringing", false, 0, "N", "", ""};
  const auto sensors = SplitList(s.params.count("sensors") ? s.params.at("sensors") : "");
  if (sensors.empty()) return Fail(r, "the check needs 'sensors' (e.g. [rfsensor, lfsensor])");
  const auto rows = Window(t, s.Number("after", 0), s.Number("until", 1e30));
  if (rows.size() < 3) return Fail(r, "no logged data in the window");
  const auto& time = t.col(t.Column("time"));
  const double dt = (time[rows.back()] - time[rows.front()]) / (rows.size() - 1);
  const int half = std::max(1, static_cast<int>(std::lround(0.5 * s.Number("window") / dt)));
  std::string worst;
  for (const auto& name : sensors) {
    const int c = t.Column(name + "_fz");
    if (c < 0) return Fail(r, "no force sensor '" + name + "' in the log");
    const auto& f = t.col(c);
    double sum2 = 0;
    for (size_t k = 0; k < rows.size(); ++k) {
      const size_t lo = k >= static_cast<size_t>(half) ? k - half : 0;
      const size_t hi = std::min(rows.size() - 1, k + half);
      double mean = 0;
      for (size_t j = lo; j <= hi; ++j) mean += f[rows[j]];
      mean /= (hi - lo + 1);
      sum2 += (f[rows[k]] - mean) * (f[rows[k]] - mean);
    }
    const double rms = std::sqrt(sum2 / rows.size());
    if (rms >= r.value) {
      r.value = rms;
      worst = name;
    }
  }
  const double max = s.Number("max", 1e30);
  r.passed = r.value <= max;
  r.limit = "<= " + Fmt(max) + " N";
  r.detail = "RMS of fz less its " + Fmt(s.Number("window") * 1e3) +
             " ms moving average, largest at " + worst;
  return r;
}

CheckResult MaxRejected(const CheckSpec& s, const nlohmann::json& sim) {
  CheckResult r{"max_rejected", false, 0, "", "", ""};
  r.value = sim.value("rejected_commands", 0.0);
  r.passed = r.value <= s.Number("max");
  r.limit = "<= " + Fmt(s.Number("max"));
  r.detail = "joint commands rejected by the servo";
  return r;
}

CheckResult RealTimeFactor(const CheckSpec& s, const nlohmann::json& sim) {
  CheckResult r{"real_time_factor", false, 0, "x", "", ""};
  r.value = sim.value("real_time_factor", 0.0);
  r.passed = r.value >= s.Number("min", 0);
  r.limit = ">= " + Fmt(s.Number("min", 0));
  r.detail = "simulated over wall time";
  return r;
}

// sim_host's self_collision effect (sim_host/self_collision_watch.h): its summary's
// "self_collision" {cycles_in_contact, pairs: [{pair, first_time, deepest, cycles}]}
CheckResult SelfCollisions(const CheckSpec& s, const nlohmann::json& sim) {
  CheckResult r{"self_collisions", false, 0, "cycles", "", ""};
  const auto it = sim.find("self_collision");
  if (it == sim.end() || !it->is_object())
    return Fail(r, "sim_host did not check self-collisions (its self_collision effect was off: "
                   "a scenario's 'effects: {self_collision: off}' overrides the check's request)");
  const nlohmann::json& sc = *it;
  std::string pairs;
  bool expected_seen = false;
  const std::string want = s.Has("pair") ? s.params.at("pair") : "";
  const auto slash = want.find('/');
  const std::string flipped = slash == std::string::npos ? want : want.substr(slash + 1) + "/" + want.substr(0, slash);
  double expected_cycles = 0;
  for (const auto& p : sc.value("pairs", nlohmann::json::array())) {
    const std::string name = p.value("pair", std::string());
    pairs += (pairs.empty() ? "" : "; ") + name + " from " + Fmt(p.value("first_time", 0.0)) +
             " s, deepest " + Fmt(1e3 * p.value("deepest", 0.0)) + " mm";
    if (!want.empty() && (name == want || name == flipped)) {
      expected_seen = true;
      expected_cycles = p.value("cycles", 0.0);
    }
  }
  const std::string checked = Fmt(sc.value("pairs_checked", 0.0)) + " link pairs checked in " +
                              Fmt(sc.value("checks", 0.0)) + " cycles";
  if (s.Has("min_distance_mm")) {
    // the closest approach of the simulated links over the run (negative: penetration)
    const double limit = s.Number("min_distance_mm", 0);
    const bool exact = sc.value("closest_exact", false);
    r.unit = "mm";
    r.value = sc.value("closest_mm", -1e9);
    r.passed = r.value >= limit;
    r.limit = ">= " + Fmt(limit) + " mm";
    r.detail = checked + "; closest approach " +
               (exact ? Fmt(r.value) + " mm (" + sc.value("closest_pair", std::string()) +
                            " at " + Fmt(sc.value("closest_t", 0.0)) + " s)"
                      : "above " + Fmt(r.value) + " mm") +
               "; in contact: " + (pairs.empty() ? "none" : pairs);
    return r;
  }
  if (!want.empty()) {
    r.value = expected_cycles;
    r.passed = expected_seen;
    r.limit = want + " in contact";
    r.detail = checked + "; in contact: " + (pairs.empty() ? "none" : pairs);
    return r;
  }
  r.value = sc.value("cycles_in_contact", 0.0);
  r.passed = r.value <= s.Number("max");
  r.limit = "<= " + Fmt(s.Number("max"));
  r.detail = checked + "; in contact: " + (pairs.empty() ? "none" : pairs);
  return r;
}

// the controller's self-collision guard as sim_host recorded it (sim_host/guard_watch.h): its
// summary's "self_collision_guard" {hold_episodes, held_cycles, holding_at_end, first, closest}
CheckResult SelfCollisionHolds(const CheckSpec& s, const nlohmann::json& sim) {
  CheckResult r{"self_collision_holds", false, 0, "holds", "", ""};
  const auto it = sim.find("self_collision_guard");
  if (it == sim.end() || !it->is_object())
    return Fail(r, "sim_host's summary has no self_collision_guard (a sim_host older than the "
                   "segment's guard record?)");
  const nlohmann::json& g = *it;
  const auto pair = [](const nlohmann::json& x) {
    if (!x.is_object()) return std::string("none");
    return x.value("pair", std::string()) + " at " + Fmt(x.value("distance_mm", 0.0)) +
           " mm (t=" + Fmt(x.value("time", 0.0)) + " s)";
  };
  r.value = g.value("hold_episodes", 0.0);
  r.passed = r.value <= s.Number("max");
  r.limit = "<= " + Fmt(s.Number("max"));
  r.detail = Fmt(g.value("held_cycles", 0.0)) + " command blocks held; first " +
             pair(g.value("first", nlohmann::json())) + ", closest " +
             pair(g.value("closest", nlohmann::json())) +
             (g.value("holding_at_end", false) ? "; still holding at the end" : "");
  return r;
}

// still standing after a push (runner/recovery.h)
CheckResult Standing(const CheckSpec& s, const datalog::Table& t, const nlohmann::json& sim) {
  CheckResult r{"standing", false, 0, "m", "", ""};
  if (!s.Has("stance_at") || !s.Has("after"))
    return Fail(r, "the check needs 'stance_at' (e.g. the push's start) and 'after' [s]");
  StandingSpec spec;
  spec.stance_at = s.Number("stance_at", 0);
  spec.after = s.Number("after", 0);
  spec.min_height_fraction = s.Number("min_height_fraction");
  spec.max_tilt_deg = s.Number("max_tilt_deg");
  if (s.Has("sensors")) spec.sensors = SplitList(s.params.at("sensors"));
  spec.load_tolerance = s.Number("load_tolerance");
  StandingResult m;
  std::string error;
  if (!MeasureStanding(t, sim, spec, &m, &error)) return Fail(r, error);
  r.value = m.lowest_height;
  r.passed = m.standing;
  r.limit = ">= " + Fmt(spec.min_height_fraction) + " x stance, tilt <= " + Fmt(spec.max_tilt_deg) + " deg";
  r.detail = m.why;
  return r;
}

// base and ankle torques settle after a push (runner/recovery.h)
CheckResult Settles(const CheckSpec& s, const datalog::Table& t) {
  CheckResult r{"settles", false, 0, "s", "", ""};
  if (!s.Has("at")) return Fail(r, "the check needs 'at', the push's start [s]");
  SettleSpec spec;
  spec.at = s.Number("at", 0);
  spec.duration = s.Number("duration");
  spec.baseline = s.Number("baseline");
  spec.tolerance = s.Number("tolerance");
  spec.fraction = s.Number("fraction");
  spec.within = s.Number("within");
  if (s.Has("sensors")) spec.sensors = SplitList(s.params.at("sensors"));
  SettleResult m;
  std::string error;
  if (!MeasureSettling(t, spec, &m, &error)) return Fail(r, error);
  r.value = std::max(m.base_time, m.torque_time);
  r.passed = m.settled;
  r.limit = "<= " + Fmt(spec.within) + " s after the push";
  r.detail = "base within " + Fmt(spec.tolerance * 1e3) + " mm of its stance after " +
             Fmt(m.base_time) + " s (largest excursion " + Fmt(m.base_excursion * 1e3) +
             " mm); ankle torque oscillation below " + Fmt(spec.fraction * 100) +
             " % of its first peak (" + Fmt(m.first_peak) + " N m) after " + Fmt(m.torque_time) + " s";
  return r;
}

}  // namespace

std::vector<std::string> SplitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

CheckResult Evaluate(const CheckSpec& spec, const datalog::Table& log, const nlohmann::json& sim) {
  try {
    if (spec.type == "max_rejected") return MaxRejected(spec, sim);
    if (spec.type == "real_time_factor") return RealTimeFactor(spec, sim);
    if (spec.type == "self_collisions") return SelfCollisions(spec, sim);
    if (spec.type == "self_collision_holds") return SelfCollisionHolds(spec, sim);
    if (log.Column("time") < 0 || log.Column("base_z") < 0)
      return Fail({spec.type, false, 0, "", "", ""}, "the data log has no time/base columns");
    if (spec.type == "base_height") return BaseHeight(spec, log);
    if (spec.type == "not_fallen") return NotFallen(spec, log);
    if (spec.type == "feet_carry_weight") return FeetCarryWeight(spec, log, sim);
    if (spec.type == "base_displacement") return BaseDisplacement(spec, log);
    if (spec.type == "force_ringing") return ForceRinging(spec, log);
    if (spec.type == "standing") return Standing(spec, log, sim);
    if (spec.type == "settles") return Settles(spec, log);
    if (spec.type == "cop_inside") return CopInside(spec, log, sim);
    if (spec.type == "foot_lifted") return FootLifted(spec, log);
    if (spec.type == "goal_reached") return GoalReached(spec, log);
    if (spec.type == "average_speed") return AverageSpeed(spec, log);
    if (spec.type == "ball_centred") return BallCentred(spec, log, sim);
    if (spec.type == "obstacle_contacts") return ObstacleContacts(spec, log, sim);
    if (spec.type == "obstacle_clearance") return ObstacleClearance(spec, log, sim);
  } catch (const std::exception& e) {
    return Fail({spec.type, false, 0, "", "", ""}, std::string("bad parameter: ") + e.what());
  }
  return Fail({spec.type, false, 0, "", "", ""}, "unknown check type (known: " + CheckTypeNames() + ")");
}

}  // namespace ohrp::runner
