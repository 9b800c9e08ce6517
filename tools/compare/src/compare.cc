// Two data logs held against each other (see compare.h).
#include "compare/compare.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "cli/plausible.h"
#include "compare/coherence.h"
#include "compare/signal.h"

namespace ohrp::compare {
namespace {

namespace fs = std::filesystem;
constexpr int kExitOk = 0, kExitUsage = 2;

// columns that are no measurement
bool Bookkeeping(const std::string& n) { return n == "time" || n == "status" || n == "rejected" || n == "guard_holding"; }

std::string Join(const std::vector<std::string>& v, size_t most = 12) {
  std::string s;
  for (size_t i = 0; i < v.size() && i < most; ++i) s += (i ? ", " : "") + v[i];
  if (v.size() > most) s += ", ... (" + std::to_string(v.size()) + " in all)";
  return s;
}

// the first time `c` crosses `v` upwards (`above`) or downwards; NAN when never
double FirstCrossing(const datalog::Table& t, int time_col, int c, double v, bool above) {
  const auto& x = t.col(c);
  const auto& tt = t.col(time_col);
  for (size_t i = 1; i < x.size(); ++i) {
    const bool crossed = above ? (x[i - 1] <= v && x[i] > v) : (x[i - 1] >= v && x[i] < v);
    if (crossed) return tt[i - 1] + (v - x[i - 1]) / (x[i] - x[i - 1]) * (tt[i] - tt[i - 1]);
  }
  return NAN;
}

// the summary JSON of a log for event:NAME
std::string SummaryOf(const std::string& log, const std::string& given) {
  if (!given.empty()) return given;
  const fs::path dir = fs::path(log).parent_path();
  for (const char* name : {"sim_summary.json", "summary.json"}) {
    std::error_code ec;
    if (fs::exists(dir / name, ec)) return (dir / name).string();
  }
  return "";
}

// the first event `name` in `summary`; false with *error
bool EventTime(const std::string& summary, const std::string& log, const std::string& name,
               double* time, std::string* error) {
  if (summary.empty()) {
    *error = "event:" + name + " needs the events of '" + log +
             "': no sim_summary.json or summary.json beside it (give --summary-a/--summary-b)";
    return false;
  }
  std::ifstream in(summary);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("events") || !j["events"].is_array()) {
    *error = summary + ": not a summary with an \"events\" list";
    return false;
  }
  std::set<std::string> names;
  for (const auto& e : j["events"]) {
    if (!e.is_object() || !e.contains("event") || !e.contains("time")) continue;
    const std::string n = e["event"].is_string() ? e["event"].get<std::string>() : "";
    if (n == name && e["time"].is_number()) {
      *time = e["time"].get<double>();
      return true;
    }
    names.insert(n);
  }
  *error = summary + ": no event '" + name + "' (it has: " +
           Join(std::vector<std::string>(names.begin(), names.end())) + ")";
  return false;
}

// An oscillation of one log whose first swing is within 6 noise sigma of the other log's channel
// could not be seen in the other: not reported (a simulation's micro-rocking against a robot's
// noisy sensor)
void DropBelowTheOthersNoise(Oscillation* o, double other_noise, const char* other) {
  if (!o->found || o->amplitude > 3 * other_noise) return;  // amplitude: half the first swing
  char buf[200];
  std::snprintf(buf, sizeof(buf), "its swing (%.3g) is within the noise of the channel in %s (6 sigma: %.3g)",
                2 * o->amplitude, other, 6 * other_noise);
  const double noise = o->noise;
  *o = Oscillation{};
  o->noise = noise;
  o->why = buf;
}

}  // namespace

int Compare(const CompareOptions& o, Comparison* out, std::string* error) {
  datalog::Table a, b;
  if (!a.Load(o.a, error) || !b.Load(o.b, error)) return kExitUsage;
  const int ta = a.Column("time"), tb = b.Column("time");
  if (ta < 0 || tb < 0) {
    *error = (ta < 0 ? o.a : o.b) + ": no 'time' column (not a data log of sim_host or hw_driver)";
    return kExitUsage;
  }
  if (a.rows() < 3 || b.rows() < 3) {
    *error = (a.rows() < 3 ? o.a : o.b) + ": fewer than 3 rows";
    return kExitUsage;
  }
  for (const datalog::Table* t : {&a, &b}) {
    const auto& tt = t->col(t == &a ? ta : tb);
    // times of the file: a plausible run's (a time of 1e300 makes every window absurd)
    *error = cli::CheckPlausibleEach("time", tt, (t == &a ? o.a : o.b) + ": time");
    if (!error->empty()) return kExitUsage;
    for (size_t i = 1; i < tt.size(); ++i) {
      if (!(tt[i] > tt[i - 1])) {
        *error = (t == &a ? o.a : o.b) + ":" + std::to_string(i + 2) +
                 ": the time does not increase (" + std::to_string(tt[i]) + " after " +
                 std::to_string(tt[i - 1]) + ")";
        return kExitUsage;
      }
    }
  }
  std::vector<std::string> common;
  for (const auto& n : a.names())
    if (!Bookkeeping(n) && b.Column(n) >= 0) common.push_back(n);
  if (common.empty()) {
    *error = "the logs have no channel in common (" + o.a + ": " + Join(a.names()) + "; " + o.b +
             ": " + Join(b.names()) + ")";
    return kExitUsage;
  }
  auto check_channel = [&](const std::string& n, const char* what) {
    if (a.Column(n) >= 0 && b.Column(n) >= 0 && !Bookkeeping(n)) return true;
    *error = std::string(what) + ": no channel '" + n + "' in " +
             (a.Column(n) < 0 ? o.a : o.b) + " (channels in both: " + Join(common) + ")";
    return false;
  };
  std::vector<std::string> channels = o.channels.empty() ? common : o.channels;
  for (const auto& n : channels)
    if (!check_channel(n, "--channels")) return kExitUsage;
  for (const auto& n : o.oscillating) {
    if (!check_channel(n, "--oscillation")) return kExitUsage;
    if (std::find(channels.begin(), channels.end(), n) == channels.end()) channels.push_back(n);
  }

  //---- alignment
  std::string align = o.align;
  if (align.empty()) {
    const std::string first = !o.channels.empty() ? o.channels.front()
                              : !o.oscillating.empty() ? o.oscillating.front() : "";
    if (first.empty()) {
      *error = "say how to align the logs: --align xcorr:CHANNEL (e.g. xcorr:" + common.front() +
               "), event:NAME, event:CHANNEL>VALUE or none; or name --channels (the first is "
               "cross-correlated)";
      return kExitUsage;
    }
    align = "xcorr:" + first;
  }
  const auto& tA = a.col(ta);
  const auto& tB = b.col(tb);
  if (align == "none") {
    out->lag = 0;
    out->align_detail = "none: lag 0";
  } else if (align.rfind("xcorr:", 0) == 0) {
    const std::string ch = align.substr(6);
    if (!check_channel(ch, "--align")) return kExitUsage;
    std::string why;
    std::vector<double> tw, xw;  // A within [from, to]: only the window pulls the lag
    Slice(tA, a.col(a.Column(ch)), o.from, o.to, &tw, &xw);
    if (!CrossCorrelationLag(tw, xw, tB, b.col(b.Column(ch)), 0.0, o.max_lag, &out->lag, &why)) {
      *error = "--align " + align + ": " + why;
      return kExitUsage;
    }
    out->align_detail = "cross-correlation of " + ch +
                        (std::isfinite(o.from) || std::isfinite(o.to) ? " within the window" : "");
  } else if (align.rfind("event:", 0) == 0) {
    const std::string ev = align.substr(6);
    const size_t op = ev.find_first_of("<>");
    double t_a = NAN, t_b = NAN;
    if (op != std::string::npos) {
      const std::string ch = ev.substr(0, op);
      char* end = nullptr;
      const std::string vs = ev.substr(op + 1);
      const double v = std::strtod(vs.c_str(), &end);
      if (vs.empty() || *end != 0 || !std::isfinite(v)) {
        *error = "--align " + align + ": '" + vs + "' is not a number (want event:CHANNEL>VALUE)";
        return kExitUsage;
      }
      if (!check_channel(ch, "--align")) return kExitUsage;
      t_a = FirstCrossing(a, ta, a.Column(ch), v, ev[op] == '>');
      t_b = FirstCrossing(b, tb, b.Column(ch), v, ev[op] == '>');
      if (std::isnan(t_a) || std::isnan(t_b)) {
        *error = "--align " + align + ": " + ch + " never " + (ev[op] == '>' ? "rises above " : "falls below ") +
                 vs + " in " + (std::isnan(t_a) ? o.a : o.b);
        return kExitUsage;
      }
    } else {
      if (!EventTime(SummaryOf(o.a, o.summary_a), o.a, ev, &t_a, error) ||
          !EventTime(SummaryOf(o.b, o.summary_b), o.b, ev, &t_b, error))
        return kExitUsage;
      // the events' times are numbers of the summaries: plausible times of a run
      for (const auto& [t, log] : {std::pair{t_a, o.a}, std::pair{t_b, o.b}}) {
        *error = cli::CheckPlausible("time", t, "the summary of " + log + ": event " + ev + " time");
        if (!error->empty()) return kExitUsage;
      }
    }
    out->lag = t_b - t_a;
    char buf[160];
    std::snprintf(buf, sizeof(buf), "event %s at %.6g s in A, %.6g s in B", ev.c_str(), t_a, t_b);
    out->align_detail = buf;
  } else {
    *error = "--align '" + align + "': want xcorr:CHANNEL, event:NAME, event:CHANNEL>VALUE, "
             "event:CHANNEL<VALUE or none";
    return kExitUsage;
  }

  //---- the window: A's times within both logs and [from, to]
  out->from = std::max({o.from, tA.front(), tB.front() - out->lag});
  out->to = std::min({o.to, tA.back(), tB.back() - out->lag});
  std::vector<size_t> rows;
  for (size_t i = 0; i < tA.size(); ++i)
    if (tA[i] >= out->from && tA[i] <= out->to) rows.push_back(i);
  if (rows.size() < 3) {
    char buf[200];
    std::snprintf(buf, sizeof(buf), "the common window [%.6g, %.6g] s (A's time, lag %.6g s) holds %zu rows of A: "
                  "check --from/--to and the alignment", out->from, out->to, out->lag, rows.size());
    *error = buf;
    return kExitUsage;
  }
  out->samples = rows.size();

  //---- per channel
  out->channels.clear();
  std::vector<double> wt, wa, wb;  // A's times and values in the window, B's aligned to them
  for (size_t i : rows) wt.push_back(tA[i]);
  for (const auto& n : channels) {
    ChannelResult r;
    r.name = n;
    const auto& xa = a.col(a.Column(n));
    const auto& xb = b.col(b.Column(n));
    // A's window and B aligned to it, once: the differences, the correlation and the motion
    // are all read from them
    wa.clear();
    wb.clear();
    size_t cursor = 0;
    for (size_t i : rows) {
      wa.push_back(xa[i]);
      wb.push_back(Interpolate(tB, xb, tA[i] + out->lag, &cursor));
    }
    double s2 = 0, sum = 0, ma = 0, sa2 = 0;
    for (double v : wa) ma += v;
    ma /= static_cast<double>(wa.size());
    for (size_t k = 0; k < wa.size(); ++k) {
      const double d = wb[k] - wa[k];
      s2 += d * d;
      sum += d;
      sa2 += (wa[k] - ma) * (wa[k] - ma);
      if (std::fabs(d) > std::fabs(r.peak)) {
        r.peak = d;
        r.peak_time = wt[k];
      }
    }
    const double count = static_cast<double>(rows.size());
    r.correlation = Correlation(wa, wb);
    r.moves_a = Moves(wa);
    r.moves_b = Moves(wb);
    r.rms = std::sqrt(s2 / count);
    r.bias = sum / count;
    r.rms_a = std::sqrt(sa2 / count);
    std::string why;
    double lag = 0;
    if (CrossCorrelationLag(wt, wa, tB, xb, out->lag, 0.25, &lag, &why)) {
      r.has_lag = true;
      r.lag = lag;
    }
    if (std::find(o.oscillating.begin(), o.oscillating.end(), n) != o.oscillating.end()) {
      r.oscillating = true;
      r.osc_a = AnalyseOscillation(tA, xa, out->from, out->to);
      r.osc_b = AnalyseOscillation(tB, xb, out->from + out->lag, out->to + out->lag);
      DropBelowTheOthersNoise(&r.osc_a, r.osc_b.noise, "B");
      DropBelowTheOthersNoise(&r.osc_b, r.osc_a.noise, "A");
    }
    out->channels.push_back(std::move(r));
  }

  //---- the same experiment?
  std::vector<std::string> names;
  std::vector<double> correlation;
  std::vector<bool> moving;
  for (const auto& r : out->channels) {
    names.push_back(r.name);
    correlation.push_back(r.correlation);
    moving.push_back(r.moves_a && r.moves_b);
  }
  out->coherence = JudgeCoherence(names, correlation, moving, o.min_coherence);
  if (!out->coherence.same) {
    *error = "the logs do not hold the same experiment: " + out->coherence.detail +
             " (the alignment: " + out->align_detail + "; other --from/--to or --align, or "
             "--min-coherence 0 to compare anyway)";
    return kExitDifferent;
  }
  return kExitOk;
}

}  // namespace ohrp::compare
