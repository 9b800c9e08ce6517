// Whether two logs hold the same experiment (ohrp compare-logs): after the alignment, each
// channel that moves above its noise in both logs is correlated (Pearson) between A and the
// aligned B over the window; the logs are the same experiment when the median correlation of
// those channels reaches a threshold (--min-coherence, default 0.5). Two unrelated runs (a
// stand against a walk, a push from the left against one from the right) correlate near 0 or
// below; the same run on another contact model or on the robot stays near 1 on the channels
// that move.
#pragma once

#include <string>
#include <vector>

namespace ohrp::compare {

// The samples of (t, x) with t in [lo, hi].
void Slice(const std::vector<double>& t, const std::vector<double>& x, double lo, double hi,
           std::vector<double>* ts, std::vector<double>* xs);

// Pearson's correlation of a and b (same length); NAN when either is constant.
double Correlation(const std::vector<double>& a, const std::vector<double>& b);

// A channel "moves" when its spread about its mean exceeds both 3 noise sigma (NoiseSigma) and a
// millionth of its magnitude (a smaller swing is numerical, not motion).
bool Moves(const std::vector<double>& x);

struct Coherence {
  int moving = 0;            // channels that move in both logs
  double median = 0;         // their median correlation (NAN: none moves)
  bool same = true;          // median >= the threshold, or nothing to judge by
  std::string detail;        // a sentence for the table and the error
};

// The verdict from the channels' correlations (`moving_both[i]`: channel i moves in both logs).
Coherence JudgeCoherence(const std::vector<std::string>& names, const std::vector<double>& correlation,
                         const std::vector<bool>& moving_both, double threshold);

}  // namespace ohrp::compare
