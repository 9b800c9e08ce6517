// The comparison's outputs: compare.json's content and the table on stdout (see compare.h).
#include <cmath>
#include <cstdio>
#include <string>

#include "compare/compare.h"

namespace ohrp::compare {

namespace {

nlohmann::json OscJson(const Oscillation& o) {
  if (!o.found) return {{"found", false}, {"why", o.why}};
  return {{"found", true},
          {"method", o.method},
          {"frequency", o.frequency},
          {"frequency_se", o.frequency_se},
          {"natural_frequency", o.natural_frequency},
          {"sigma", o.sigma},
          {"sigma_se", o.sigma_se},
          {"log_decrement", o.log_decrement},
          {"log_decrement_se", o.log_decrement_se},
          {"decay_ratio", o.decay_ratio},
          {"damping_ratio", o.damping_ratio},
          {"amplitude", o.amplitude},
          {"noise", o.noise},
          {"extrema", o.extrema},
          {"first", o.first},
          {"last", o.last},
          {"extremum_times", o.extremum_times},
          {"extremum_values", o.extremum_values}};
}

}  // namespace

nlohmann::json ToJson(const CompareOptions& o, const Comparison& c) {
  nlohmann::json j;
  j["a"] = {{"log", o.a}, {"label", o.label_a}};
  j["b"] = {{"log", o.b}, {"label", o.label_b}};
  j["lag"] = c.lag;
  j["alignment"] = c.align_detail;
  j["window"] = {c.from, c.to};
  j["samples"] = c.samples;
  j["same_experiment"] = c.coherence.same;
  j["coherence"] = {{"moving_channels", c.coherence.moving},
                    {"median_correlation", std::isnan(c.coherence.median) ? nlohmann::json(nullptr)
                                                                          : nlohmann::json(c.coherence.median)},
                    {"threshold", o.min_coherence},
                    {"detail", c.coherence.detail}};
  nlohmann::json ch = nlohmann::json::array();
  for (const auto& r : c.channels) {
    nlohmann::json e = {{"name", r.name}, {"rms", r.rms},           {"peak", r.peak},
                        {"peak_time", r.peak_time}, {"bias", r.bias}, {"rms_a", r.rms_a}};
    e["lag"] = r.has_lag ? nlohmann::json(r.lag) : nlohmann::json(nullptr);
    e["alignment_lag"] = c.lag;  // the lag B was compared at
    e["correlation"] = std::isnan(r.correlation) ? nlohmann::json(nullptr) : nlohmann::json(r.correlation);
    e["moves"] = {{"a", r.moves_a}, {"b", r.moves_b}};
    if (r.oscillating) {
      e["oscillation"] = {{"a", OscJson(r.osc_a)}, {"b", OscJson(r.osc_b)}};
      if (r.osc_a.found && r.osc_b.found) {
        e["oscillation"]["frequency_difference"] = r.osc_b.frequency - r.osc_a.frequency;
        e["oscillation"]["log_decrement_difference"] = r.osc_b.log_decrement - r.osc_a.log_decrement;
      }
    }
    ch.push_back(e);
  }
  j["channels"] = ch;
  return j;
}

std::string Table(const Comparison& c) {
  std::string s;
  char buf[400];
  std::snprintf(buf, sizeof(buf), "alignment: %s; lag of B behind A %.4f s; window [%.3f, %.3f] s of A (%zu rows)\n\n",
                c.align_detail.c_str(), c.lag, c.from, c.to, c.samples);
  s += buf;
  s += "same experiment: " + std::string(c.coherence.same ? "yes" : "NO") + " (" + c.coherence.detail + ")\n";
  s += "every channel is compared at that lag; 'lag' is its own by cross-correlation, 'corr' its\n"
       "correlation with the aligned B ('-': flat), 'moves' whether it moves above its noise in A, B\n\n";
  std::snprintf(buf, sizeof(buf), "%-28s %12s %12s %9s %12s %12s %10s %7s %5s\n", "channel", "rms(B-A)",
                "peak(B-A)", "at [s]", "mean(B-A)", "rms(A-mean)", "lag [s]", "corr", "moves");
  s += buf;
  for (const auto& r : c.channels) {
    char lag[32] = "-", corr[32] = "-";
    if (r.has_lag) std::snprintf(lag, sizeof(lag), "%.4f", r.lag);
    if (!std::isnan(r.correlation)) std::snprintf(corr, sizeof(corr), "%.3f", r.correlation);
    const std::string moves = std::string(r.moves_a ? "A" : "-") + (r.moves_b ? "B" : "-");
    std::snprintf(buf, sizeof(buf), "%-28s %12.5g %12.5g %9.3f %12.5g %12.5g %10s %7s %5s\n", r.name.c_str(),
                  r.rms, r.peak, r.peak_time, r.bias, r.rms_a, lag, corr, moves.c_str());
    s += buf;
  }
  bool any = false;
  for (const auto& r : c.channels) any = any || r.oscillating;
  if (!any) return s;
  std::snprintf(buf, sizeof(buf), "\n%-28s %4s %16s %16s %10s %9s %7s\n", "oscillation", "log",
                "f_d [Hz]", "log decrement", "ratio/per", "zeta", "extrema");
  s += buf;
  for (const auto& r : c.channels) {
    if (!r.oscillating) continue;
    for (int k = 0; k < 2; ++k) {
      const Oscillation& o = k == 0 ? r.osc_a : r.osc_b;
      if (!o.found) {
        std::snprintf(buf, sizeof(buf), "%-28s %4s not found: %s\n", r.name.c_str(), k ? "B" : "A",
                      o.why.c_str());
      } else {
        std::snprintf(buf, sizeof(buf), "%-28s %4s %8.4f+-%-7.4f %8.4f+-%-7.4f %10.4f %9.4f %7d\n",
                      r.name.c_str(), k ? "B" : "A", o.frequency, o.frequency_se, o.log_decrement,
                      o.log_decrement_se, o.decay_ratio, o.damping_ratio, o.extrema);
      }
      s += buf;
    }
  }
  return s;
}

}  // namespace ohrp::compare
