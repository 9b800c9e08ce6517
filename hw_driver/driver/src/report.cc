// Reports of a driver run: the lateness table, the stats/summary JSON (see program.h).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hw_driver/program.h"

namespace ohrp::hw {

std::string LatenessTable(const LatenessHistogram& h) {
  char line[160];
  std::string s = "  lateness [us]        cycles\n";
  for (const auto& b : h.Octaves()) {
    std::snprintf(line, sizeof(line), "  %9.3f - %-9.3f %10lu\n", b.lo_ns * 1e-3, b.hi_ns * 1e-3,
                  static_cast<unsigned long>(b.count));
    s += line;
  }
  std::snprintf(line, sizeof(line),
                "  n %lu  p50 %.1f us  p90 %.1f us  p99 %.1f us  p99.9 %.1f us  max %.1f us\n",
                static_cast<unsigned long>(h.count()), h.Percentile(50) * 1e-3,
                h.Percentile(90) * 1e-3, h.Percentile(99) * 1e-3, h.Percentile(99.9) * 1e-3,
                h.max_ns() * 1e-3);
  s += line;
  return s;
}

namespace {

// the part of the run's time spent spinning (0..1)
double SpinFraction(const LiveStats& live, const DriverOptions& o) {
  const double run = static_cast<double>(live.cycles.load() + live.skipped.load()) * o.period;
  return run > 0 ? static_cast<double>(live.spin_ns.load()) * 1e-9 / run : 0.0;
}

}  // namespace

std::string WakeCost(const LiveStats& live, const DriverOptions& o) {
  if (o.wake.mode == WakeMode::kSleep) return "";
  char line[120];
  std::snprintf(line, sizeof(line), ", margin %.1f us, spinning %.1f %% of the time",
                live.wake_margin_ns.load() * 1e-3, 100.0 * SpinFraction(live, o));
  return line;
}

bool WriteStats(const std::string& path, const ProgramOptions& o, const shm::ProducerConfig& robot,
                const LiveStats& live, const DriverResult* result) {
  using nlohmann::json;
  const LatenessHistogram& h = live.lateness;
  json j;
  if (result != nullptr) {
    j["outcome"] = result->outcome;
    j["detail"] = result->detail;
    j["exit_code"] = result->exit_code;
    j["duration"] = result->duration;
    j["safe_mode"] = result->safe_mode;
    j["safe_mode_cycle"] = result->safe_mode_cycle;
    j["recoveries"] = result->recoveries;
    j["rt"] = result->rt.Describe();
    j["rt_warnings"] = result->rt.warnings;
    json events = json::array();
    for (const Event& e : result->events) {
      json ev = {{"cycle", e.cycle}, {"time", e.time}, {"event", EventName(e.kind)},
                 {"value", e.value}};
      if (e.board >= 0) ev["board"] = e.board;
      if (e.joint >= 0) {
        ev["joint"] = e.joint;
        if (e.joint < static_cast<int>(robot.joint_names.size()))
          ev["joint_name"] = robot.joint_names[e.joint];
      }
      if (e.reading != 0 || e.joint >= 0 || e.kind == EventKind::kFall ||
          e.kind == EventKind::kGuardHoldBegin || e.kind == EventKind::kGuardHoldEnd) {
        if (std::isfinite(e.reading)) {
          ev["reading"] = e.reading;
        } else {
          ev["reading"] = std::isnan(e.reading) ? "nan" : e.reading > 0 ? "inf" : "-inf";
        }
      }
      events.push_back(ev);
    }
    j["events"] = events;
    j["events_dropped"] = result->events_dropped;
    json per_joint = json::object();
    for (size_t i = 0; i < result->rejected_per_joint.size() && i < robot.joint_names.size();
         ++i) {
      per_joint[robot.joint_names[i]] = result->rejected_per_joint[i];
    }
    j["rejected_per_joint"] = per_joint;
  } else {
    j["outcome"] = "running";
    j["state"] = DriverStateName(static_cast<DriverState>(live.state.load()));
  }
  j["model"] = o.model;
  j["io_plugin"] = o.io_plugin;
  j["segment"] = o.segment;
  j["robot"] = robot.robot_name;
  j["period"] = o.driver.period;
  j["cycles"] = live.cycles.load();
  j["deadline_misses"] = live.deadline_misses.load();
  j["skipped_cycles"] = live.skipped.load();
  j["commands"] = live.commands.load();
  j["late_commands"] = live.late_commands.load();
  j["rejected_commands"] = live.rejected.load();
  j["clamped_commands"] = live.clamped.load();
  j["silent_reads"] = live.silent_reads.load();
  j["packets_lost"] = live.packets_lost.load();
  j["wake"] = {{"mode", WakeModeName(o.driver.wake.mode)},
               {"margin_us", live.wake_margin_ns.load() * 1e-3},
               {"spin_fraction", SpinFraction(live, o.driver)}};
  json bins = json::array();
  for (const auto& b : h.Octaves()) {
    bins.push_back({{"lo_us", b.lo_ns * 1e-3}, {"hi_us", b.hi_ns * 1e-3}, {"count", b.count}});
  }
  j["lateness"] = {{"count", h.count()},           {"mean_us", h.mean_ns() * 1e-3},
                   {"p50_us", h.Percentile(50) * 1e-3}, {"p90_us", h.Percentile(90) * 1e-3},
                   {"p99_us", h.Percentile(99) * 1e-3}, {"p999_us", h.Percentile(99.9) * 1e-3},
                   {"max_us", h.max_ns() * 1e-3},   {"histogram", bins}};

  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) return false;
    out << j.dump(2) << "\n";
    if (!out) return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  return !ec;
}

}  // namespace ohrp::hw
