// Sampling that finds candidates for the pre-processing (collision/prune.h): postures within
// joint ranges, local descents of a pair's distance, and the scan of a joint's range into cells
// whose samples keep a pair clear. Nothing here decides that a pair is pruned: the proof does
// (collision/prune_bound.h).
#pragma once

#include <random>
#include <utility>
#include <string>
#include <vector>

#include "collision/prune.h"
#include "collision/self_collision.h"

namespace ohrp::collision::prune_search {

// "12.3 mm"
std::string Mm(double d);

// postures within joint ranges: uniform, or at a limit with probability limit_share
class Sampler {
 public:
  Sampler(const PruneOptions& o, std::vector<double> lo, std::vector<double> hi)
      : o_(o), lo_(std::move(lo)), hi_(std::move(hi)), rng_(o.seed) {}
  std::vector<double>& lo() { return lo_; }
  std::vector<double>& hi() { return hi_; }
  const std::vector<double>& lo() const { return lo_; }
  const std::vector<double>& hi() const { return hi_; }

  void Sample(std::vector<double>* q) {
    q->resize(lo_.size());
    for (size_t j = 0; j < lo_.size(); ++j) {
      const double u = uniform_(rng_);
      if (u < o_.limit_share) (*q)[j] = u < 0.5 * o_.limit_share ? lo_[j] : hi_[j];
      else (*q)[j] = lo_[j] + uniform_(rng_) * (hi_[j] - lo_[j]);
    }
  }
  // a posture within [lo, hi] (by joint id), a share of joints at a bound
  void SampleIn(const std::vector<double>& lo, const std::vector<double>& hi, std::vector<double>* q) {
    q->resize(lo.size());
    for (size_t j = 0; j < lo.size(); ++j) {
      const double u = uniform_(rng_);
      if (u < o_.limit_share) (*q)[j] = u < 0.5 * o_.limit_share ? lo[j] : hi[j];
      else (*q)[j] = lo[j] + uniform_(rng_) * (hi[j] - lo[j]);
    }
  }
  double Uniform(double a, double b) { return a + uniform_(rng_) * (b - a); }

 private:
  const PruneOptions& o_;
  std::vector<double> lo_, hi_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
};

// A local descent of pair p's distance from posture q over `joints` within [lo, hi]; the closest
// distance found (stops once at or below keep).
double Descend(SelfCollision& c, LinkPair p, const std::vector<int>& joints, std::vector<double> q,
               const std::vector<double>& lo, const std::vector<double>& hi, double keep);

}  // namespace ohrp::collision::prune_search
