// The online self-collision check, one Filter per cycle (the set-up is in
// self_collision_guard_setup.cc): predict the motion (the interval each joint can reach, a
// nominal motion and its envelope), certify every pair along it, or brake.
#include "controllers/self_collision_guard.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ohrp::controllers {

void SelfCollisionGuard::ListPairs() {
  list_.clear();
  std::fill(on_list_.begin(), on_list_.end(), 0);
  for (size_t i = 0; i < always_; ++i) list_.push_back(static_cast<int>(i)), on_list_[i] = 1;
  for (size_t ri = 0; ri < file_.ranges.size(); ++ri) {
    const auto& r = file_.ranges[ri];
    if (box_lo_[r.joint] >= r.lo && box_hi_[r.joint] <= r.hi) continue;  // the box keeps to it
    for (int k : range_pairs_[ri])
      if (!on_list_[k]) list_.push_back(k), on_list_[k] = 1;
  }
}

bool SelfCollisionGuard::Certify(int i, double* bound) {
  const double* c = &coef_[static_cast<size_t>(i) * nq_];
  const double limit = limit_[i];
  const collision::LinkPair p = every_[i];
  const double horizon = 2 * period_;
  // how far the pair's links can be from the nominal motion's
  double envelope = 0;
  for (int j = 0; j < nq_; ++j)
    if (c[j] > 0) envelope += c[j] * envelope_[j];
  // from time t on: the links' speed bound (each joint's speed does not grow once it brakes)
  // and the length of the rest of their nominal paths
  const auto speed_at = [&](double t, double* rest) {
    double speed = 0;
    *rest = 0;
    for (int j = 0; j < njoint_; ++j) {
      if (c[j] <= 0) continue;
      if (t < horizon) {
        speed += c[j] * speed_[j];
        *rest += c[j] * (speed_[j] * (horizon - t) + v1_[j] * v1_[j] / (2 * decel_[j]));
      } else {
        const double s = std::max(0.0, std::abs(v1_[j]) - decel_[j] * (t - horizon));
        speed += c[j] * s;
        *rest += c[j] * s * s / (2 * decel_[j]);
      }
    }
    return speed;
  };
  // conservative advancement along the nominal motion from the measured posture: at time t
  // the distance less the envelope less what the links can travel until the next time stays
  // at or above the limit; the next time is as far as that allows
  double rest = 0;
  double speed = speed_at(0, &rest);
  double d = check_->distance(i);
  if (d - envelope - rest >= limit) return true;  // the whole motion at once
  if (!check_->measured_now(i) || d > check_cutoff_) {
    // a lower bound only (skipped, or farther than the check's cutoff): measure it with this
    // pair's own
    if (budget_ <= 0) return false;  // out of work this cycle: not certified
    --budget_, ++last_evaluations_;
    checker_->SetPoseOf(q_, p.a, p.b);  // this pair's links only
    d = checker_->Distance(p.a, p.b, limit + envelope + rest);
    check_->Record(i, d);  // next cycles bound it from this (less the links' travel)
  }
  double t = 0;
  *bound = d - envelope;
  while (true) {
    const double room = d - envelope - limit;
    *bound = std::min(*bound, d - envelope);
    if (room < 0) return false;       // the motion may come closer than the limit
    if (rest <= room) return true;    // the rest of it cannot
    if (budget_ <= 0) return false;   // out of work this cycle: not certified
    t += std::max(room / speed, 1e-6 * horizon_end_);
    speed = speed_at(t, &rest);
    Nominal(t);
    checker_->SetPoseOf(centre_, p.a, p.b);
    --budget_, ++last_evaluations_;
    d = checker_->Distance(p.a, p.b, limit + envelope + rest);
  }
}

bool SelfCollisionGuard::BrakeHelps(int i) {
  if (!brakeable_[i]) return false;
  // how far the joints the brake acts on can move the pair's links along this cycle's motion
  // (the command for the horizon, then their path to rest, and its envelope): when that alone
  // can bring the pair within the tolerance of its limit, the brake decides its approach and
  // the pair is braked (a pair already within the tolerance of its limit always is); else what
  // can still bring it there is the support legs' motion, which no brake changes: monitored.
  // From one cycle to the next the motion stays within this bound (the horizon holds one
  // period of latency), so a pair monitored now is braked in time by the brakeable joints.
  const double* c = &coef_[static_cast<size_t>(i) * nq_];
  double share = 0;
  bool acts = false;  // some joint the brake acts on this cycle moves the pair
  for (int j = 0; j < njoint_; ++j)
    if (c[j] > 0 && !Supports(j)) {
      acts = true;
      share += c[j] * (speed_[j] * 2 * period_ + v1_[j] * v1_[j] / (2 * decel_[j]) + envelope_[j]);
    }
  if (!acts) return false;  // only loaded legs move it: monitored
  const double reach = limit_[i] + tolerance_ + share;  // closer than this: braked
  double d = check_->distance(i);
  if (d >= reach) return false;
  if (check_->measured_now(i) && d <= check_cutoff_) return true;  // measured: it is that close
  // only a lower bound (the check skipped it): measure it before braking for it (walking: the
  // bounds of pairs the legs move decay to just above the check's cutoff every few cycles)
  if (budget_ <= 0) return true;  // out of work: braked, the safe side
  --budget_, ++last_evaluations_;
  const collision::LinkPair p = every_[i];
  checker_->SetPoseOf(q_, p.a, p.b);
  d = checker_->Distance(p.a, p.b, reach);
  check_->Record(i, d);
  return d < reach;
}

void SelfCollisionGuard::Brake(const shm::SensorBlock& sensors, shm::CommandBlock* c) {
  bool leg = false;
  // a retreating joint's ramp goes to its retreat velocity at its braking rate, every
  // retreating joint's change scaled by one factor (the retreat's direction kept)
  double factor = 1.0;
  for (int j = 0; j < njoint_; ++j) {
    if (Supports(j) || !(chain_[j] || retreat_[j])) {  // a loaded leg, a joint off the chains
      braked_[j] = 0;                                    // and the retreat: the controller's
      continue;
    }
    if (!braked_[j]) {
      // the brake starts here (the hold begins, or the foot has just left the ground): from
      // the measured state, at the prediction's rate
      if (std::isfinite(sensors.q[j])) brake_q_[j] = sensors.q[j];
      brake_v_[j] = std::isfinite(sensors.dq[j]) ? sensors.dq[j] : 0.0;
      brake_decel_[j] = decel_[j];
      braked_[j] = 1;
    }
    const double change = std::abs(retreat_v_[j] - brake_v_[j]);
    if (retreat_[j] && change > brake_decel_[j] * period_)
      factor = std::min(factor, brake_decel_[j] * period_ / change);
  }
  for (int j = 0; j < njoint_; ++j) {
    if (!braked_[j]) continue;
    leg = leg || CarriesFoot(j);
    const double v0 = brake_v_[j], dv = brake_decel_[j] * period_;
    const double v1 = retreat_[j] ? v0 + factor * (retreat_v_[j] - v0)
                      : v0 > 0    ? std::max(0.0, v0 - dv)
                                  : std::min(0.0, v0 + dv);
    brake_q_[j] += 0.5 * (v0 + v1) * period_;
    brake_v_[j] = v1;
    shm::JointCommand& jc = c->joint[j];
    if (jc.mode != shm::JointMode::kPosition || !(jc.kp > 0)) {
      jc.mode = shm::JointMode::kPosition;
      jc.kp = kp_default_[j];
      jc.kd = kd_default_[j];
      jc.tau_ff = 0.0;
    }
    brake_ff_[j] = std::isfinite(jc.tau_ff) ? jc.tau_ff : 0.0;  // the controller's own
    jc.q_ref = brake_q_[j];
    jc.dq_ref = v1;
    // the ramp's deceleration as a feed-forward torque (at the largest inertia: the torque the
    // prediction's braking rate was derived from), so that the servo follows the ramp from its
    // first cycle instead of building a tracking error first (which let the joint coast past
    // the ramp's end: 0.044 rad at HRP-1S's shoulder after a jump)
    // The torque is the ramp's mean deceleration over this period ((v0 - v1) / period: a ramp
    // that ends within the period asks for less) times the SMALLEST inertia the joint may
    // drive: with light rotors (G1: 0.01 kg m^2 against 2.2 at its waist) the largest inertia's
    // torque applied to the rotor alone reversed the joint within a period (G1 standing: the
    // waist at 2.2 rad/s after one braked cycle); the servo's gains add what a heavier joint
    // needs. On HRP-1S (reflected rotors: 12 of 12-25 kg m^2) it is nearly the same torque.
    jc.tau_ff = brake_ff_[j] + (v1 - v0) / period_ * file_.dynamics[j].inertia_min;
  }
  if (leg) ++leg_brake_cycles_;
}

bool SelfCollisionGuard::Filter(const shm::SensorBlock& sensors, shm::CommandBlock* c) {
  const bool predicted = Predict(sensors, *c);
  if (measuring_) return MeasureFirstCycle(sensors, c);
  if (!predicted) return Unjudged(sensors, c);
  TrackMeasuredLimits();
  int worst = -1;
  double bound = INFINITY;
  const bool certified = CertifyMotion(&worst, &bound);
  // a pair a support leg is closing: the brakeable side moves away (self_collision_retreat.cc)
  const bool retreat = PlanRetreat();
  if (retreat) {
    if (!retreating_) ++retreats_;
    ++retreat_cycles_;
  }
  retreating_ = retreat;
  if (certified && !retreat) {
    braking_ = false;
    std::fill(braked_.begin(), braked_.end(), 0);
    return false;
  }
  if (certified) {  // only the retreat: the other joints follow the controller
    braking_ = false;
    std::fill(chain_.begin(), chain_.end(), 0);
    Brake(sensors, c);
    return true;
  }
  if (monitor_only_) {  // counted, the commands left alone
    ++warned_cycles_;
    if (worst >= 0 && bound < warned_distance_) warned_distance_ = bound, warned_pair_ = every_[worst];
    braking_ = false;
    return false;
  }
  Hold(sensors, worst, bound, c);
  return true;
}

bool SelfCollisionGuard::MeasureFirstCycle(const shm::SensorBlock& sensors,
                                           shm::CommandBlock* c) noexcept {
  // the first cycle after activation: no acceleration measured yet, so the load the joints
  // carry is unknown (within the gravity bound: a box metres wide on G1's light rotors). The
  // command is replaced by the brake from the measured state (a hold where the joints stand
  // still), whose acceleration and torque the next cycle measures; not a hold episode
  measuring_ = false;
  braking_ = false;
  if (monitor_only_) return false;  // monitoring: the commands are left alone
  std::fill(braked_.begin(), braked_.end(), 0);  // Brake starts each joint from its measurement
  std::fill(chain_.begin(), chain_.end(), 1);    // nothing judged yet: every joint
  std::fill(retreat_.begin(), retreat_.end(), 0);
  Brake(sensors, c);
  return true;
}

bool SelfCollisionGuard::Unjudged(const shm::SensorBlock& sensors, shm::CommandBlock* c) noexcept {
  // a measurement is not finite: nothing to predict from, so nothing is judged (the
  // controller's own non-finite handling holds); a brake under way goes on (it needs none)
  ++unjudged_cycles_;
  std::fill(retreat_.begin(), retreat_.end(), 0);  // nothing to retreat along: to rest
  retreating_ = false;
  if (!braking_) return false;
  ++held_cycles_;
  Brake(sensors, c);
  return true;
}

void SelfCollisionGuard::TrackMeasuredLimits() noexcept {
  // the measured posture's distances: each pair's limit follows its farthest distance since
  // (a close pair may leave, not creep closer); one below its limit is counted
  check_->MoveTo(q_);
  ListPairs();
  check_->Check(list_, check_cutoff_);
  for (int i : list_) {
    const double d = check_->distance(i);
    if (d < limit_[i] - 1e-6) {
      ++violations_;
      if (d < violation_distance_) violation_distance_ = d, violation_pair_ = every_[i];
      limit_[i] = d - tolerance_;
    } else {
      limit_[i] = std::min(base_limit_[i], std::max(limit_[i], d - tolerance_));
    }
  }
}

void SelfCollisionGuard::MarkChain(int i) noexcept {
  // the joints that move one link of the pair relative to the other (coef_ > 0: a common
  // ancestor's joint moves both links and has none)
  const double* c = &coef_[static_cast<size_t>(i) * nq_];
  for (int j = 0; j < njoint_; ++j)
    if (c[j] > 0) chain_[j] = 1;
}

bool SelfCollisionGuard::CertifyMotion(int* worst, double* predicted) noexcept {
  bool clear = true;
  budget_ = kBudget;
  last_evaluations_ = 0;
  std::fill(chain_.begin(), chain_.end(), 0);
  // the pairs the brake acts on first (the work bound is theirs), then those moved by support
  // legs only: monitored, never braked
  int unbrakeable = -1;
  double unbrakeable_bound = INFINITY;
  for (int pass = 0; pass < 2 && clear && unbrakeable < 0; ++pass) {
    // the monitored pairs change no command: a small share of the work, and a pair left
    // uncertified by it is not reported
    if (pass == 1) budget_ = std::min(budget_, kMonitorBudget);
    for (int i : list_) {
      if (BrakeHelps(i) != (pass == 0)) continue;
      double b = INFINITY;
      if (Certify(i, &b)) continue;
      if (pass == 1) {
        if (budget_ <= 0) break;  // out of work: not judged
        unbrakeable = i, unbrakeable_bound = b;
        break;
      }
      // not certified: its chain is braked; the other braked pairs are judged too (each
      // brings its own chain), until the work bound runs out: then every joint (the pairs
      // not judged may need any of them)
      if (clear || b < *predicted) *worst = i, *predicted = b;
      clear = false;
      MarkChain(i);
      if (budget_ <= 0) {
        ++uncertified_cycles_;
        std::fill(chain_.begin(), chain_.end(), 1);
        break;
      }
    }
  }
  if (clear && unbrakeable >= 0) {
    ++warned_cycles_;
    if (unbrakeable_bound < warned_distance_)
      warned_distance_ = unbrakeable_bound, warned_pair_ = every_[unbrakeable];
  }
  return clear;
}

void SelfCollisionGuard::Hold(const shm::SensorBlock& sensors, int worst, double predicted,
                              shm::CommandBlock* c) noexcept {
  // brake: from the measured state when the hold begins, then along the ramp
  if (!braking_) {
    ++holds_;
    // each joint's brake starts from its measured state at the prediction's rate (Brake)
    std::fill(braked_.begin(), braked_.end(), 0);
  }
  braking_ = true;
  ++held_cycles_;
  if (worst >= 0) {
    if (first_time_ < 0) {
      first_time_ = sensors.time;
      first_pair_ = every_[worst];
      first_distance_ = predicted;
    }
    if (predicted < closest_distance_ || closest_pair_.a < 0) {
      closest_distance_ = std::isfinite(predicted) ? predicted : closest_distance_;
      closest_pair_ = every_[worst];
    }
  }
  Brake(sensors, c);
}

}  // namespace ohrp::controllers
