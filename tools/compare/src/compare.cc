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

// The comparison's stages over two loaded logs; each false with *error_ (and code_) set.
class Comparer {
 public:
  Comparer(const CompareOptions& o, Comparison* out, std::string* error)
      : o_(o), out_(out), error_(error) {}

  bool Load();            // both logs: a time column, 3 rows, plausible increasing times
  bool ChooseChannels();  // the channels compared: given, or every one in both
  bool Align();           // out->lag from --align (or the first channel's cross-correlation)
  bool Window();          // A's rows within both logs and [from, to]
  void Channels();        // each channel's figures in the window
  bool SameExperiment();  // the coherence of the moving channels
  int code() const { return code_; }

 private:
  bool Fail(int code, const std::string& what) {
    *error_ = what;
    code_ = code;
    return false;
  }
  bool CheckTimes(const datalog::Table& t, int col, const std::string& path);
  bool CheckChannel(const std::string& n, const char* what);
  bool AlignOnCrossing(const std::string& align, const std::string& ev, size_t op, double* t_a,
                       double* t_b);
  bool AlignOnEvent(const std::string& ev, double* t_a, double* t_b);
  ChannelResult Channel(const std::string& n, const std::vector<double>& wt);

  const CompareOptions& o_;
  Comparison* out_;
  std::string* error_;
  int code_ = kExitOk;
  datalog::Table a_, b_;
  int ta_ = -1, tb_ = -1;  // their time columns
  std::vector<std::string> common_, channels_;
  std::vector<size_t> rows_;  // A's rows in the window
  std::vector<double> wa_, wb_;  // scratch: a channel's window in A, B aligned to it
};

bool Comparer::Load() {
  if (!a_.Load(o_.a, error_) || !b_.Load(o_.b, error_)) return Fail(kExitUsage, *error_);
  ta_ = a_.Column("time");
  tb_ = b_.Column("time");
  if (ta_ < 0 || tb_ < 0)
    return Fail(kExitUsage, (ta_ < 0 ? o_.a : o_.b) +
                                ": no 'time' column (not a data log of sim_host or hw_driver)");
  if (a_.rows() < 3 || b_.rows() < 3)
    return Fail(kExitUsage, (a_.rows() < 3 ? o_.a : o_.b) + ": fewer than 3 rows");
  return CheckTimes(a_, ta_, o_.a) && CheckTimes(b_, tb_, o_.b);
}

// times of the file: a plausible run's (a time of 1e300 makes every window absurd), increasing
bool Comparer::CheckTimes(const datalog::Table& t, int col, const std::string& path) {
  const auto& tt = t.col(col);
  if (std::string e = cli::CheckPlausibleEach("time", tt, path + ": time"); !e.empty())
    return Fail(kExitUsage, e);
  for (size_t i = 1; i < tt.size(); ++i)
    if (!(tt[i] > tt[i - 1]))
      return Fail(kExitUsage, path + ":" + std::to_string(i + 2) + ": the time does not increase (" +
                                  std::to_string(tt[i]) + " after " + std::to_string(tt[i - 1]) + ")");
  return true;
}

bool Comparer::CheckChannel(const std::string& n, const char* what) {
  if (a_.Column(n) >= 0 && b_.Column(n) >= 0 && !Bookkeeping(n)) return true;
  return Fail(kExitUsage, std::string(what) + ": no channel '" + n + "' in " +
                              (a_.Column(n) < 0 ? o_.a : o_.b) + " (channels in both: " +
                              Join(common_) + ")");
}

bool Comparer::ChooseChannels() {
  for (const auto& n : a_.names())
    if (!Bookkeeping(n) && b_.Column(n) >= 0) common_.push_back(n);
  if (common_.empty())
    return Fail(kExitUsage, "the logs have no channel in common (" + o_.a + ": " + Join(a_.names()) +
                                "; " + o_.b + ": " + Join(b_.names()) + ")");
  channels_ = o_.channels.empty() ? common_ : o_.channels;
  for (const auto& n : channels_)
    if (!CheckChannel(n, "--channels")) return false;
  for (const auto& n : o_.oscillating) {
    if (!CheckChannel(n, "--oscillation")) return false;
    if (std::find(channels_.begin(), channels_.end(), n) == channels_.end()) channels_.push_back(n);
  }
  return true;
}

bool Comparer::Align() {
  std::string align = o_.align;
  if (align.empty()) {
    const std::string first = !o_.channels.empty()      ? o_.channels.front()
                              : !o_.oscillating.empty() ? o_.oscillating.front()
                                                        : "";
    if (first.empty())
      return Fail(kExitUsage, "say how to align the logs: --align xcorr:CHANNEL (e.g. xcorr:" +
                                  common_.front() + "), event:NAME, event:CHANNEL>VALUE or none; "
                                  "or name --channels (the first is cross-correlated)");
    align = "xcorr:" + first;
  }
  if (align == "none") {
    out_->lag = 0;
    out_->align_detail = "none: lag 0";
    return true;
  }
  if (align.rfind("xcorr:", 0) == 0) {
    const std::string ch = align.substr(6);
    if (!CheckChannel(ch, "--align")) return false;
    std::string why;
    std::vector<double> tw, xw;  // A within [from, to]: only the window pulls the lag
    Slice(a_.col(ta_), a_.col(a_.Column(ch)), o_.from, o_.to, &tw, &xw);
    if (!CrossCorrelationLag(tw, xw, b_.col(tb_), b_.col(b_.Column(ch)), 0.0, o_.max_lag, &out_->lag,
                             &why))
      return Fail(kExitUsage, "--align " + align + ": " + why);
    out_->align_detail = "cross-correlation of " + ch +
                         (std::isfinite(o_.from) || std::isfinite(o_.to) ? " within the window" : "");
    return true;
  }
  if (align.rfind("event:", 0) != 0)
    return Fail(kExitUsage, "--align '" + align + "': want xcorr:CHANNEL, event:NAME, "
                            "event:CHANNEL>VALUE, event:CHANNEL<VALUE or none");
  const std::string ev = align.substr(6);
  const size_t op = ev.find_first_of("<>");
  double t_a = NAN, t_b = NAN;
  if (!(op != std::string::npos ? AlignOnCrossing(align, ev, op, &t_a, &t_b)
                                : AlignOnEvent(ev, &t_a, &t_b)))
    return false;
  out_->lag = t_b - t_a;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "event %s at %.6g s in A, %.6g s in B", ev.c_str(), t_a, t_b);
  out_->align_detail = buf;
  return true;
}

// event:CHANNEL>VALUE (or <): the first crossing in each log
bool Comparer::AlignOnCrossing(const std::string& align, const std::string& ev, size_t op,
                               double* t_a, double* t_b) {
  const std::string ch = ev.substr(0, op);
  char* end = nullptr;
  const std::string vs = ev.substr(op + 1);
  const double v = std::strtod(vs.c_str(), &end);
  if (vs.empty() || *end != 0 || !std::isfinite(v))
    return Fail(kExitUsage, "--align " + align + ": '" + vs + "' is not a number (want event:CHANNEL>VALUE)");
  if (!CheckChannel(ch, "--align")) return false;
  *t_a = FirstCrossing(a_, ta_, a_.Column(ch), v, ev[op] == '>');
  *t_b = FirstCrossing(b_, tb_, b_.Column(ch), v, ev[op] == '>');
  if (std::isnan(*t_a) || std::isnan(*t_b))
    return Fail(kExitUsage, "--align " + align + ": " + ch + " never " +
                                (ev[op] == '>' ? "rises above " : "falls below ") + vs + " in " +
                                (std::isnan(*t_a) ? o_.a : o_.b));
  return true;
}

// event:NAME: the first such event in each log's summary
bool Comparer::AlignOnEvent(const std::string& ev, double* t_a, double* t_b) {
  if (!EventTime(SummaryOf(o_.a, o_.summary_a), o_.a, ev, t_a, error_) ||
      !EventTime(SummaryOf(o_.b, o_.summary_b), o_.b, ev, t_b, error_))
    return Fail(kExitUsage, *error_);
  // the events' times are numbers of the summaries: plausible times of a run
  for (const auto& [t, log] : {std::pair{*t_a, o_.a}, std::pair{*t_b, o_.b}}) {
    if (std::string e = cli::CheckPlausible("time", t, "the summary of " + log + ": event " + ev + " time");
        !e.empty())
      return Fail(kExitUsage, e);
  }
  return true;
}

bool Comparer::Window() {
  const auto& tA = a_.col(ta_);
  const auto& tB = b_.col(tb_);
  out_->from = std::max({o_.from, tA.front(), tB.front() - out_->lag});
  out_->to = std::min({o_.to, tA.back(), tB.back() - out_->lag});
  for (size_t i = 0; i < tA.size(); ++i)
    if (tA[i] >= out_->from && tA[i] <= out_->to) rows_.push_back(i);
  if (rows_.size() < 3) {
    char buf[200];
    std::snprintf(buf, sizeof(buf), "the common window [%.6g, %.6g] s (A's time, lag %.6g s) holds %zu rows of A: "
                  "check --from/--to and the alignment", out_->from, out_->to, out_->lag, rows_.size());
    return Fail(kExitUsage, buf);
  }
  out_->samples = rows_.size();
  return true;
}

void Comparer::Channels() {
  out_->channels.clear();
  std::vector<double> wt;  // A's times in the window
  for (size_t i : rows_) wt.push_back(a_.col(ta_)[i]);
  for (const auto& n : channels_) out_->channels.push_back(Channel(n, wt));
}

// one channel: A's window and B aligned to it, once: the differences, the correlation and the
// motion are all read from them
ChannelResult Comparer::Channel(const std::string& n, const std::vector<double>& wt) {
  const auto& tA = a_.col(ta_);
  const auto& tB = b_.col(tb_);
  ChannelResult r;
  r.name = n;
  const auto& xa = a_.col(a_.Column(n));
  const auto& xb = b_.col(b_.Column(n));
  wa_.clear();
  wb_.clear();
  size_t cursor = 0;
  for (size_t i : rows_) {
    wa_.push_back(xa[i]);
    wb_.push_back(Interpolate(tB, xb, tA[i] + out_->lag, &cursor));
  }
  double s2 = 0, sum = 0, ma = 0, sa2 = 0;
  for (double v : wa_) ma += v;
  ma /= static_cast<double>(wa_.size());
  for (size_t k = 0; k < wa_.size(); ++k) {
    const double d = wb_[k] - wa_[k];
    s2 += d * d;
    sum += d;
    sa2 += (wa_[k] - ma) * (wa_[k] - ma);
    if (std::fabs(d) > std::fabs(r.peak)) {
      r.peak = d;
      r.peak_time = wt[k];
    }
  }
  const double count = static_cast<double>(rows_.size());
  r.correlation = Correlation(wa_, wb_);
  r.moves_a = Moves(wa_);
  r.moves_b = Moves(wb_);
  r.rms = std::sqrt(s2 / count);
  r.bias = sum / count;
  r.rms_a = std::sqrt(sa2 / count);
  std::string why;
  double lag = 0;
  if (CrossCorrelationLag(wt, wa_, tB, xb, out_->lag, 0.25, &lag, &why)) {
    r.has_lag = true;
    r.lag = lag;
  }
  if (std::find(o_.oscillating.begin(), o_.oscillating.end(), n) != o_.oscillating.end()) {
    r.oscillating = true;
    r.osc_a = AnalyseOscillation(tA, xa, out_->from, out_->to);
    r.osc_b = AnalyseOscillation(tB, xb, out_->from + out_->lag, out_->to + out_->lag);
    DropBelowTheOthersNoise(&r.osc_a, r.osc_b.noise, "B");
    DropBelowTheOthersNoise(&r.osc_b, r.osc_a.noise, "A");
  }
  return r;
}

bool Comparer::SameExperiment() {
  std::vector<std::string> names;
  std::vector<double> correlation;
  std::vector<bool> moving;
  for (const auto& r : out_->channels) {
    names.push_back(r.name);
    correlation.push_back(r.correlation);
    moving.push_back(r.moves_a && r.moves_b);
  }
  out_->coherence = JudgeCoherence(names, correlation, moving, o_.min_coherence);
  if (out_->coherence.same) return true;
  return Fail(kExitDifferent,
              "the logs do not hold the same experiment: " + out_->coherence.detail +
                  " (the alignment: " + out_->align_detail + "; other --from/--to or --align, "
                  "or --min-coherence 0 to compare anyway)");
}

}  // namespace

int Compare(const CompareOptions& o, Comparison* out, std::string* error) {
  Comparer c(o, out, error);
  if (!c.Load() || !c.ChooseChannels() || !c.Align() || !c.Window()) return c.code();
  c.Channels();
  if (!c.SameExperiment()) return c.code();
  return kExitOk;
}

}  // namespace ohrp::compare
