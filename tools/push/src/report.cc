// The push tool's report: markdown table, CSV, JSON and the plot (see push/push.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "push/push.h"
#include "tool_process/run_command.h"

namespace fs = std::filesystem;

namespace ohrp::push {
namespace {

std::string Fmt(const char* format, double v) {
  if (std::isinf(v)) return v > 0 ? "never" : "-inf";
  char b[64];
  std::snprintf(b, sizeof(b), format, v);
  return b;
}

// one cell of the bisection table
std::string LimitCell(const Limit& l) {
  if (l.failed) return "error";
  return (l.above_max ? ">= " : "") + Fmt("%.1f", l.largest);
}

// one cell of the settle table
std::string SettleCell(const Limit& l) {
  if (l.failed) return "error";
  const Trial& t = l.settle;
  return Fmt("%.3f", t.base_time) + " (" + Fmt("%.1f", t.base_excursion * 1e3) + " mm) / " +
         Fmt("%.3f", t.torque_time) + (t.standing ? "" : " (fell)");
}

// JSON numbers cannot be infinite: null instead
nlohmann::json Num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace

bool WriteReport(const PushOptions& o, const std::vector<Limit>& results, std::string* markdown,
                 std::string* error) {
  const bool settle = o.settle_impulse > 0;
  const size_t nd = o.directions.size();

  //---------------- markdown ----------------
  std::ostringstream md;
  char b[512];
  if (settle) {
    std::snprintf(b, sizeof(b),
                  "Settling after a %.1f N s push over %.2f s: time after the push's end until the base "
                  "stays within %.0f mm of its stance / the ankle torque oscillation stays below %.0f %% "
                  "of its first peak [s]; in brackets the base's largest horizontal excursion\n\n",
                  o.settle_impulse, o.push_duration, o.settle_tolerance * 1e3, o.settle_fraction * 100);
  } else {
    std::snprintf(b, sizeof(b),
                  "Largest impulse survived [N s] (push over %.2f s at the base, bisection on [0, %.0f] "
                  "to %.1f N s; standing = %.1f s after the push, base above 80 %% of its stance "
                  "height, tilt below 30 deg, feet carry the weight)\n\n",
                  o.push_duration, o.max_impulse, o.tolerance, o.observe);
  }
  md << b << "| direction [deg] |";
  for (const auto& c : o.controllers) md << " " << c << " |";
  md << "\n|---:|";
  for (size_t k = 0; k < o.controllers.size(); ++k) md << "---:|";
  md << "\n";
  for (size_t d = 0; d < nd; ++d) {
    md << "| " << Fmt("%g", o.directions[d]) << " |";
    for (size_t c = 0; c < o.controllers.size(); ++c) {
      const Limit& l = results[c * nd + d];
      md << " " << (settle ? SettleCell(l) : LimitCell(l)) << " |";
    }
    md << "\n";
  }
  *markdown = md.str();

  //---------------- files ----------------
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  std::ofstream table(o.out_dir + "/table.md"), csv(o.out_dir + "/push.csv"), js(o.out_dir + "/push.json");
  if (!table || !csv || !js) {
    *error = "cannot write into '" + o.out_dir + "'";
    return false;
  }
  table << *markdown;
  nlohmann::json j;
  j["mode"] = settle ? "settle" : "bisection";
  j["options"] = {{"controllers", o.controllers}, {"directions_deg", o.directions},
                  {"scene", o.scene}, {"keyframe", o.keyframe}, {"push_at", o.push_at},
                  {"push_duration", o.push_duration}, {"observe", o.observe}, {"window", o.window},
                  {"max_impulse", o.max_impulse}, {"tolerance", o.tolerance},
                  {"settle_impulse", o.settle_impulse}, {"settle_tolerance", o.settle_tolerance},
                  {"settle_fraction", o.settle_fraction}, {"settle_within", o.settle_within},
                  {"physics_dt", 0.001}, {"control_period", 0.005}, {"contact", "soft"}};
  j["results"] = nlohmann::json::array();
  if (settle) {
    csv << "controller,direction_deg,impulse_Ns,standing,base_settle_s,torque_settle_s,first_peak_Nm,"
           "base_excursion_m,settled,failed\n";
  } else {
    csv << "controller,direction_deg,largest_impulse_Ns,smallest_fall_Ns,above_max,trials,failed\n";
  }
  for (const Limit& l : results) {
    nlohmann::json r = {{"controller", l.controller}, {"direction_deg", l.direction},
                        {"failed", l.failed}, {"detail", l.detail}, {"trials", l.trials}};
    if (settle) {
      const Trial& t = l.settle;
      r.update({{"impulse", t.impulse}, {"standing", t.standing}, {"base_settle_time", Num(t.base_time)},
                {"torque_settle_time", Num(t.torque_time)}, {"first_peak", t.first_peak},
                {"base_excursion", t.base_excursion},
                {"settled", t.settled}, {"run", t.dir}});
      csv << '"' << l.controller << "\"," << l.direction << "," << t.impulse << "," << t.standing
          << "," << t.base_time << "," << t.torque_time << "," << t.first_peak << "," << t.base_excursion << "," << t.settled
          << "," << l.failed << "\n";
    } else {
      r.update({{"largest_impulse", l.largest}, {"smallest_fall", l.smallest_fall},
                {"above_max", l.above_max}});
      csv << '"' << l.controller << "\"," << l.direction << "," << l.largest << ","
          << l.smallest_fall << "," << l.above_max << "," << l.trials << "," << l.failed << "\n";
    }
    j["results"].push_back(r);
  }
  js << j.dump(2) << "\n";
  table.close();
  csv.close();
  js.close();  // the plot reads push.csv

  //---------------- plot ----------------
  if (o.plot && !settle) {
    const std::string python = fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string why;  // an argument vector, no shell (tool_process/run_command.h)
    if (tool::RunCommand({python, o.source_dir + "/tools/push/plot_push.py", o.out_dir + "/push.csv",
                          o.out_dir + "/push.png"},
                         o.out_dir + "/plot.stderr", &why) != 0)
      std::fprintf(stderr, "ohrp_push: the plot could not be made (see %s/plot.stderr)\n", o.out_dir.c_str());
  }
  return true;
}

bool WritePhases(const PushOptions& o, const std::vector<double>& times,
                 const std::vector<std::vector<Limit>>& results, std::string* error) {
  const size_t nd = o.directions.size(), nc = o.controllers.size();
  std::ostringstream md;
  md << "Largest impulse survived [N s] per push time (columns: controller @ time [s]; push over "
     << Fmt("%.2f", o.push_duration) << " s, standing judged " << Fmt("%.1f", o.observe)
     << " s after it)\n\n| direction [deg] |";
  for (size_t c = 0; c < nc; ++c)
    for (double t : times) md << " " << o.controllers[c] << " @ " << Fmt("%.2f", t) << " |";
  md << "\n|---:|";
  for (size_t k = 0; k < nc * times.size(); ++k) md << "---:|";
  md << "\n";
  std::ofstream csv(o.out_dir + "/phases.csv");
  csv << "controller,push_at_s,direction_deg,largest_impulse_Ns,smallest_fall_Ns,above_max,failed\n";
  for (size_t d = 0; d < nd; ++d) {
    md << "| " << Fmt("%g", o.directions[d]) << " |";
    for (size_t c = 0; c < nc; ++c)
      for (size_t t = 0; t < times.size(); ++t) {
        const Limit& l = results[t][c * nd + d];
        md << " " << LimitCell(l) << " |";
        csv << '"' << o.controllers[c] << "\"," << times[t] << "," << o.directions[d] << ","
            << l.largest << "," << l.smallest_fall << "," << l.above_max << "," << l.failed << "\n";
      }
    md << "\n";
  }
  md << "| least |";
  for (size_t c = 0; c < nc; ++c)
    for (size_t t = 0; t < times.size(); ++t) {
      double least = 1e300;
      for (size_t d = 0; d < nd; ++d) least = std::min(least, results[t][c * nd + d].largest);
      md << " " << Fmt("%.1f", least) << " |";
    }
  md << "\n";
  std::ofstream table(o.out_dir + "/phases.md");
  table << md.str();
  if (!table || !csv) {
    *error = "cannot write phases.md / phases.csv into '" + o.out_dir + "'";
    return false;
  }
  std::printf("%s", md.str().c_str());
  return true;
}

}  // namespace ohrp::push
