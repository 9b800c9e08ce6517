// Two data logs of the same experiment held against each other (ohrp compare-logs): a
// simulation's (sim_host --log, ohrp_run's log.csv) and the robot's (hw_driver --log), or any
// two logs in that format (datalog/recorder.h), read with datalog::Table.
//
// 1. Alignment: the lag of B behind A, so that B(t + lag) is compared with A(t):
//      xcorr:CHANNEL   the cross-correlation of CHANNEL (signal.h), searched over +-max_lag
//      event:NAME      the first event NAME in each log's summary JSON ("events": [{"time",
//                      "event"}], as sim_host's sim_summary.json and hw_driver's --summary
//                      write them), e.g. event:push_start
//      event:CH>V, event:CH<V   the first time CHANNEL rises above (falls below) V in each log
//      none            lag 0
//    A cross-correlation looks at A's samples within [from, to] only (the rest of the logs, a
//    stand-up or a different start, does not pull the lag).
// 2. Per channel over the common window (A's times, [from, to] within both logs): the RMS of
//    B - A, its peak (largest |B - A|) and when, the mean difference, the channel's own lag
//    by cross-correlation (within +-0.25 s of the alignment's: 0 when it is the aligned channel),
//    and its correlation with the aligned B; whether it moves above its noise in each log.
// 2b. The same experiment? (coherence.h): the median correlation of the channels that move in
//    both logs against --min-coherence; below it, Compare returns kExitDifferent.
// 3. For the oscillating channels asked for: frequency, decay and damping of each log
//    (oscillation.h) over the window, and their differences.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "compare/coherence.h"
#include "compare/oscillation.h"
#include "datalog/table.h"

namespace ohrp::compare {

struct CompareOptions {
  std::string a, b;                    // the logs (CSV)
  std::string align;                   // see above; empty: xcorr on the first of `channels`
  std::vector<std::string> channels;   // compared channels; empty: every common one
  std::vector<std::string> oscillating;  // channels whose oscillation is measured
  double from = -HUGE_VAL, to = HUGE_VAL;  // [s] window, in A's time
  double max_lag = 2.0;                // [s] cross-correlation search
  double min_coherence = 0.5;          // the median correlation that makes one experiment
  std::string summary_a, summary_b;    // event:NAME's summaries; empty: sim_summary.json or
                                       // summary.json beside the log
  std::string label_a = "simulation", label_b = "robot";
};

struct ChannelResult {
  std::string name;
  double rms = 0, peak = 0, peak_time = 0, bias = 0;
  bool has_lag = false;
  double lag = 0;  // [s] B's time minus A's for this channel alone
  double rms_a = 0;  // RMS of A about its mean over the window (a scale for rms)
  double correlation = NAN;  // Pearson's, A against the aligned B over the window (NAN: flat)
  bool moves_a = false, moves_b = false;  // above the noise and a millionth of the magnitude
  bool oscillating = false;
  Oscillation osc_a, osc_b;
};

struct Comparison {
  double lag = 0;                 // [s] B's time of the same instant minus A's
  std::string align_detail;       // how it was found
  double from = 0, to = 0;        // [s] the window used, A's time
  size_t samples = 0;             // A's rows in the window
  std::vector<ChannelResult> channels;
  Coherence coherence;            // the same experiment? (coherence.h)
};

constexpr int kExitDifferent = 1;  // Compare: the logs do not hold the same experiment

// Loads, checks and compares. Exit code 2 with `*error` for bad input (a file that cannot be
// read, no common channel, an unknown channel, an alignment that cannot be done, an empty
// window); kExitDifferent (1) with `*error` when the logs do not hold the same experiment (`out`
// is filled: the figures are still reported); 0 otherwise.
int Compare(const CompareOptions& o, Comparison* out, std::string* error);

// compare.json's content, and the table printed on stdout
nlohmann::json ToJson(const CompareOptions& o, const Comparison& c);
std::string Table(const Comparison& c);

}  // namespace ohrp::compare
