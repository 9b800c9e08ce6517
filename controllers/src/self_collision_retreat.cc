// The guard's retreat (issue 29; docs/selfcollision.md, "The retreat"): a pair that a joint the
// guard may not brake (a loaded leg, a passive joint) is closing is not only held: the joints
// it may brake on the pair's chain (the arm, the torso) move away along the gradient of the
// pair's distance, fast enough that the predicted distance stays above the limit. Nothing here
// allocates, throws or logs (the vectors are sized in Configure).
#include "controllers/self_collision_guard.h"

#include <algorithm>
#include <cmath>

namespace ohrp::controllers {

double SelfCollisionGuard::PairDistance(int i, const std::vector<double>& q, double cutoff) noexcept {
  const collision::LinkPair p = every_[i];
  checker_->SetPoseOf(q, p.a, p.b);
  ++last_evaluations_;
  return checker_->Distance(p.a, p.b, cutoff);
}

bool SelfCollisionGuard::Gradient(int i, double d, int* budget, double* g) noexcept {
  const double* c = &coef_[static_cast<size_t>(i) * nq_];
  int n = 0;
  for (int j = 0; j < nq_; ++j) n += c[j] > 0;
  if (2 * n > *budget) return false;
  *budget -= 2 * n;
  const double cutoff = d + 0.05;  // far above the steps' change: every answer exact
  std::copy(q_.begin(), q_.end(), scratch_q_.begin());
  for (int j = 0; j < nq_; ++j) {
    g[j] = 0.0;
    if (c[j] <= 0) continue;
    const double h = 1e-5;  // [rad or m]: the distance changes by at most c_j h (1e-5 m)
    scratch_q_[j] = q_[j] + h;
    const double up = PairDistance(i, scratch_q_, cutoff);
    scratch_q_[j] = q_[j] - h;
    const double down = PairDistance(i, scratch_q_, cutoff);
    scratch_q_[j] = q_[j];
    g[j] = (up - down) / (2 * h);
  }
  return true;
}

bool SelfCollisionGuard::PlanRetreat() noexcept {
  nretreat_ = 0;
  std::fill(retreat_.begin(), retreat_.end(), 0);
  std::fill(retreat_v_.begin(), retreat_v_.end(), 0.0);
  if (monitor_only_) return false;
  int budget = kRetreatBudget;
  const double T = kRetreatLookahead * period_;
  for (int i : list_) {
    if (nretreat_ == kMaxRetreatPairs) break;
    const double* c = &coef_[static_cast<size_t>(i) * nq_];
    // the brakeable side and how far the other side can close the pair over the look-ahead at
    // its measured speed and acceleration (times the links' reach)
    bool brakeable = false, closed = false;
    double reach = 0;
    for (int j = 0; j < nq_; ++j) {
      if (c[j] <= 0) continue;
      if (j < njoint_ && !Supports(j)) {
        brakeable = true;
      } else {
        closed = true;
        reach += c[j] * (std::abs(meas_v_[j]) * T + 0.5 * std::abs(meas_a_[j]) * T * T);
      }
    }
    if (!brakeable || !closed) continue;
    const double target = limit_[i] + 2 * tolerance_;
    double d = check_->distance(i);
    if (d - reach >= target) continue;  // the support side cannot bring it there in time
    if (!check_->measured_now(i) || d > check_cutoff_) {
      if (budget <= 0) break;
      --budget;
      d = PairDistance(i, q_, target + reach);
      check_->Record(i, d);
      if (d - reach >= target) continue;
    }
    double* g = &retreat_grad_[static_cast<size_t>(nretreat_) * nq_];
    if (!Gradient(i, d, &budget, g)) break;
    // the support side's rate and acceleration along the gradient: the pair's distance with
    // the brakeable side still is d + s t + a t^2 / 2; its smallest value over the look-ahead
    double s = 0, a = 0;
    for (int j = 0; j < nq_; ++j)
      if (c[j] > 0 && !(j < njoint_ && !Supports(j))) s += g[j] * meas_v_[j], a += g[j] * meas_a_[j];
    double low = std::min(d, d + s * T + 0.5 * a * T * T);
    if (a > 0 && s < 0 && -s / a < T) low = std::min(low, d - 0.5 * s * s / a);
    if (low >= target) continue;
    // the brakeable side moves away at the rate the support side closes it (now or at the
    // look-ahead's end) plus what brings the prediction back to the target over the look-ahead
    const double closing = std::max({0.0, -s, -(s + a * T)});
    retreat_rate_[nretreat_] = closing + (target - low) / T;
    retreat_pairs_[nretreat_++] = i;
  }
  if (nretreat_ == 0) return false;
  SolveRetreat();
  ProjectOthers(&budget);
  return true;
}

void SelfCollisionGuard::SolveRetreat() noexcept {
  // the brakeable joints of the pairs (retreat_ 1: free; 2: locked at a limit, held)
  for (int k = 0; k < nretreat_; ++k) {
    const double* c = &coef_[static_cast<size_t>(retreat_pairs_[k]) * nq_];
    for (int j = 0; j < njoint_; ++j)
      if (c[j] > 0 && !Supports(j)) retreat_[j] = 1;
  }
  // each weighted by its inertia bound (the least kinetic energy: a torso carrying the arm
  // moves less than the arm's own joints)
  const auto weight = [&](int j) { return 1.0 / std::max(file_.dynamics[j].inertia_max, 1e-9); };
  const double T = kRetreatLookahead * period_;
  for (int pass = 0; pass < 3; ++pass) {
    std::fill(retreat_v_.begin(), retreat_v_.end(), 0.0);
    // Kaczmarz over the pairs: each pair's rate along its gradient, the least-norm change
    for (int sweep = 0; sweep < 2; ++sweep)
      for (int k = 0; k < nretreat_; ++k) {
        const double* g = &retreat_grad_[static_cast<size_t>(k) * nq_];
        double rate = 0, norm = 0;
        for (int j = 0; j < njoint_; ++j)
          if (retreat_[j] == 1) rate += g[j] * retreat_v_[j], norm += g[j] * g[j] * weight(j);
        const double missing = retreat_rate_[k] - rate;
        if (missing <= 0 || norm <= 0) continue;
        for (int j = 0; j < njoint_; ++j)
          if (retreat_[j] == 1) retreat_v_[j] += missing * g[j] * weight(j) / norm;
      }
    // a joint whose retreat would cross a limit within the look-ahead is held there and the
    // rest solved again (at most twice)
    bool locked = false;
    for (int j = 0; j < njoint_; ++j) {
      if (retreat_[j] != 1) continue;
      const double end = q_[j] + retreat_v_[j] * T;
      if (end < file_.robot.q_min[j] + 1e-3 || end > file_.robot.q_max[j] - 1e-3)
        retreat_[j] = 2, retreat_v_[j] = 0.0, locked = true;
    }
    if (!locked) break;
  }
  // the speed: one factor for every joint, so that the direction is kept
  double scale = 1.0;
  for (int j = 0; j < njoint_; ++j) {
    if (!retreat_[j] || retreat_v_[j] == 0.0) continue;
    const double vmax = file_.dynamics[j].velocity_max > 0 ? file_.dynamics[j].velocity_max
                                                          : kRetreatSpeed;
    scale = std::min(scale, vmax / std::abs(retreat_v_[j]));
  }
  for (int j = 0; j < njoint_; ++j) retreat_v_[j] *= scale;
}

void SelfCollisionGuard::ProjectOthers(int* budget) noexcept {
  // another pair of the list that the retreating joints move, measured within the target of
  // its limit: the retreat may not bring it closer (one projection each, the first few)
  for (int i : list_) {
    bool own = false;
    for (int k = 0; k < nretreat_; ++k) own = own || retreat_pairs_[k] == i;
    if (own) continue;
    const double* c = &coef_[static_cast<size_t>(i) * nq_];
    bool moved = false;
    for (int j = 0; j < njoint_; ++j) moved = moved || (retreat_[j] && c[j] > 0 && retreat_v_[j] != 0.0);
    if (!moved) continue;
    const double d = check_->distance(i);
    if (d > limit_[i] + 4 * tolerance_ + 0.01) continue;
    if (!Gradient(i, d, budget, grad_.data())) return;
    double rate = 0, norm = 0;
    for (int j = 0; j < njoint_; ++j)
      if (retreat_[j]) rate += grad_[j] * retreat_v_[j], norm += grad_[j] * grad_[j];
    if (rate >= 0 || norm <= 0) continue;
    for (int j = 0; j < njoint_; ++j)
      if (retreat_[j]) retreat_v_[j] -= rate * grad_[j] / norm;
  }
}

}  // namespace ohrp::controllers
