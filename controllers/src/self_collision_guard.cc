// The online self-collision check: the file against the header, then one Filter per cycle:
// predict the motion (the interval each joint can reach, a nominal motion and its envelope),
// certify every pair along it, or brake.
#include "controllers/self_collision_guard.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ostream>

namespace ohrp::controllers {
namespace {

std::string Hex(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof(b), "0x%llx", static_cast<unsigned long long>(v));
  return b;
}

// a torque limit the guard can use: the header's, or none (infinite) when it states none
double Limit(double tau_max) {
  return std::isfinite(tau_max) && tau_max > 0 && tau_max < 1e9 ? tau_max : INFINITY;
}

}  // namespace

SelfCollisionGuard::Owner SelfCollisionGuard::FileOwner(const std::string& path,
                                                        const shm::SegmentHeader& header,
                                                        std::string* robot) {
  collision::SelfCollisionFile f;
  std::string error;
  robot->clear();
  if (!collision::ReadSelfCollisionFile(path, &f, &error)) return Owner::kUnreadable;
  *robot = f.robot.name;
  if (f.robot.model_hash == header.model_hash) return Owner::kThisModel;
  // a producer that publishes no model identity (hash 0): no file can be verified for it
  if (header.model_hash == 0) return Owner::kUnpublished;
  const int n = std::clamp(header.njoint, 0, shm::kMaxJoints);
  bool same_joints = static_cast<int>(f.robot.joint_names.size()) == n;
  for (int j = 0; same_joints && j < n; ++j)
    same_joints = f.robot.joint_names[j] == std::string(header.joint_names[j], strnlen(header.joint_names[j], shm::kNameLen));
  const std::string name(header.robot_name, strnlen(header.robot_name, sizeof(header.robot_name)));
  return same_joints || f.robot.name == name ? Owner::kThisRobot : Owner::kAnotherRobot;
}

std::string SelfCollisionGuard::Configure(const std::string& path,
                                          const shm::SegmentHeader& header) {
  std::string error;
  if (!collision::ReadSelfCollisionFile(path, &file_, &error)) return error;
  // the same robot: model hash, joint count and names
  if (file_.robot.model_hash != header.model_hash)
    return path + ": is for robot " + file_.robot.name + " (model hash " +
           Hex(file_.robot.model_hash) + "), the segment's robot has model hash " +
           Hex(header.model_hash) + " (regenerate it with ohrp_selfcollision --model ...)";
  njoint_ = header.njoint;
  if (static_cast<int>(file_.robot.joint_names.size()) != njoint_)
    return path + ": has " + std::to_string(file_.robot.joint_names.size()) +
           " joints, the segment " + std::to_string(njoint_);
  for (int j = 0; j < njoint_; ++j)
    if (file_.robot.joint_names[j] != std::string(header.joint_names[j], strnlen(header.joint_names[j], shm::kNameLen)))
      return path + ": joint " + std::to_string(j) + " is " + file_.robot.joint_names[j] +
             ", the segment's is " + header.joint_names[j];
  // the braking check needs what the joints can do: never guessed
  if (static_cast<int>(file_.dynamics.size()) != njoint_)
    return path + ": has no dynamics: section (the joints' inertia and gravity bounds the "
                  "braking check needs): regenerate it with ohrp_selfcollision --model ... "
                  "(docs/selfcollision.md)";
  // postures: the actuated joints, then the passive ones (measured: sensors.passive_q)
  nq_ = collision::NumJoints(file_.robot);
  if (nq_ - njoint_ != header.npassive)
    return path + ": has " + std::to_string(nq_ - njoint_) + " passive joints, the segment " +
           std::to_string(header.npassive);
  checker_ = collision::SelfCollision::Create(file_.robot, &error);
  if (!checker_) return path + ": " + error;
  period_ = header.control_period;
  tolerance_ = std::max(0.5 * file_.margin, 1e-3);
  // every pair the check may need, allocated once: online, structural with floors, ranges'
  every_ = file_.online;
  base_limit_.assign(every_.size(), file_.margin);
  // Structural pairs are not checked yet: their floors come from the zero and reference
  // postures only, and HRP-1S's knee/ankle boxes overlap deeper with any knee bend past
  // half-sitting (walking, balancing), so the floor stopped ordinary motion (issue 29: the
  // floors need the postures the robot's motions use, not two)
  const bool floors = kCheckStructuralFloors &&
                      file_.structural_floor.size() == file_.structural.size();
  for (size_t k = 0; floors && k < file_.structural.size(); ++k) {
    every_.push_back(file_.structural[k]);
    base_limit_.push_back(file_.structural_floor[k]);
  }
  always_ = every_.size();
  for (const auto& r : file_.ranges)
    for (const auto& p : r.pairs)
      if (std::find(every_.begin(), every_.end(), p) == every_.end()) {
        every_.push_back(p);
        base_limit_.push_back(file_.margin);
      }
  range_pairs_.clear();
  for (const auto& r : file_.ranges) {
    range_pairs_.emplace_back();
    for (const auto& p : r.pairs)
      range_pairs_.back().push_back(
          static_cast<int>(std::find(every_.begin(), every_.end(), p) - every_.begin()));
  }
  limit_ = base_limit_;
  // the incremental check measures every pair that may be within the tolerance of its limit
  // (BrakeHelps brakes those): a lower bound it keeps for a pair is then above limit + tolerance
  // (with the margin alone, a pair's bound decaying with the support legs' travel to just
  // above the margin read as 'near its limit' and braked the arms of every walk)
  check_cutoff_ = *std::max_element(base_limit_.begin(), base_limit_.end()) + tolerance_;
  // per pair and joint, how far the pair's two links move per unit of the joint
  const auto reach = collision::LinkReach(file_.robot);
  coef_.assign(every_.size() * nq_, 0.0);
  // A joint beyond which BOTH links lie (an ancestor of both: G1's waist for its torso and
  // arms) moves them rigidly together: their distance does not depend on it, so it adds
  // nothing (with it, G1's waist settling after the stand braked the shoulder 2.9 mm from
  // the torso for 18 cycles)
  const auto moves = [&](int l, int joint) {
    for (const auto& jr : reach[l])
      if (jr.first == joint) return true;
    return false;
  };
  for (size_t i = 0; i < every_.size(); ++i)
    for (int l : {every_[i].a, every_[i].b})
      for (const auto& [joint, r] : reach[l])
        if (!(moves(every_[i].a, joint) && moves(every_[i].b, joint))) coef_[i * nq_ + joint] += r;
  // a pair the brake may act on: some actuated joint moves it. Which of them it acts on is
  // decided each cycle from the measured forces (UpdateLoads): an arm always, a leg with a foot
  // while its foot carries no load (in the air: a swing leg, a robot on its rig); a loaded leg
  // is never braked (braking a stance leg topples the robot): its pairs are monitored
  brakeable_.assign(every_.size(), 0);
  for (size_t i = 0; i < every_.size(); ++i)
    for (int j = 0; j < njoint_; ++j)
      if (coef_[i * nq_ + j] > 0) brakeable_[i] = 1;
  check_ = std::make_unique<collision::IncrementalCheck>(checker_.get(), every_);
  list_.reserve(every_.size());
  on_list_.assign(every_.size(), 0);
  // per joint: the torque limit, the servo's default gains; the braking deceleration is set
  // each cycle from the measured torque (Predict)
  tau_max_.assign(njoint_, 0.0);
  kp_default_.assign(njoint_, 0.0);
  kd_default_.assign(njoint_, 0.0);
  decel_.assign(nq_, 1.0);  // passive joints: never braked (their stop_ is 0)
  for (int j = 0; j < njoint_; ++j) {
    tau_max_[j] = Limit(header.tau_max[j]);
    kp_default_[j] = header.default_kp[j];
    kd_default_[j] = header.default_kd[j];
    decel_[j] = Deceleration(j, INFINITY);
  }
  // each joint's support sensor, by the header's force sensor names (-1: none)
  support_.assign(njoint_, -1);
  for (int j = 0; j < njoint_; ++j)
    for (int f = 0; f < std::clamp(header.nforce, 0, shm::kMaxForceSensors); ++f)
      if (!file_.dynamics[j].support_sensor.empty() &&
          file_.dynamics[j].support_sensor == std::string(header.force_names[f], strnlen(header.force_names[f], shm::kNameLen)))
        support_[j] = f;
  loaded_.assign(njoint_, 0);
  for (int j = 0; j < njoint_; ++j) loaded_[j] = CarriesFoot(j) ? 1 : 0;  // until measured
  braked_.assign(njoint_, 0);
  q_.assign(nq_, 0.0);
  box_lo_.assign(nq_, 0.0);
  box_hi_.assign(nq_, 0.0);
  brake_q_.assign(njoint_, 0.0);
  brake_v_.assign(njoint_, 0.0);
  brake_decel_.assign(decel_.begin(), decel_.begin() + njoint_);
  brake_ff_.assign(njoint_, 0.0);
  last_dq_.assign(njoint_, 0.0);
  have_last_ = false;
  centre_.assign(nq_, 0.0);
  for (auto* v : {&v0_, &a_mid_, &v1_, &q1_, &stop_, &speed_, &envelope_}) v->assign(nq_, 0.0);
  return "";
}

void SelfCollisionGuard::Activate(const shm::SensorBlock& sensors) {
  UpdateLoads(sensors, true);
  std::fill(braked_.begin(), braked_.end(), 0);
  for (int j = 0; j < njoint_; ++j) {
    q_[j] = std::isfinite(sensors.q[j]) ? sensors.q[j] : 0.0;
    brake_q_[j] = q_[j];
    brake_v_[j] = 0.0;
  }
  for (int k = njoint_; k < nq_; ++k)  // passive joints, as measured
    q_[k] = std::isfinite(sensors.passive_q[k - njoint_]) ? sensors.passive_q[k - njoint_] : 0.0;
  // each pair's limit: the margin, or less than its distance now by the tolerance
  check_->MoveTo(q_);
  const double cutoff = *std::max_element(base_limit_.begin(), base_limit_.end());
  check_->CheckAll(cutoff);
  for (size_t i = 0; i < every_.size(); ++i)
    limit_[i] = std::min(base_limit_[i], check_->distance(static_cast<int>(i)) - tolerance_);
  braking_ = false;
  // no acceleration measured yet: the first cycle measures (Filter)
  for (int j = 0; j < njoint_; ++j) last_dq_[j] = std::isfinite(sensors.dq[j]) ? sensors.dq[j] : 0.0;
  have_last_ = false;
  measuring_ = true;
}

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
  for (int j = 0; j < njoint_; ++j) {
    if (Supports(j)) {  // a loaded leg keeps the controller's command
      braked_[j] = 0;
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
    leg = leg || CarriesFoot(j);
    const double v0 = brake_v_[j], dv = brake_decel_[j] * period_;
    const double v1 = v0 > 0 ? std::max(0.0, v0 - dv) : std::min(0.0, v0 + dv);
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
  bool clear = Predict(sensors, *c);
  if (measuring_) {
    // the first cycle after activation: no acceleration measured yet, so the load the joints
    // carry is unknown (within the gravity bound: a box metres wide on G1's light rotors). The
    // command is replaced by the brake from the measured state (a hold where the joints stand
    // still), whose acceleration and torque the next cycle measures; not a hold episode
    measuring_ = false;
    braking_ = false;
    if (monitor_only_) return false;  // monitoring: the commands are left alone
    std::fill(braked_.begin(), braked_.end(), 0);  // Brake starts each joint from its measurement
    Brake(sensors, c);
    return true;
  }
  if (!clear) {
    // a measurement is not finite: nothing to predict from, so nothing is judged (the
    // controller's own non-finite handling holds); a brake under way goes on (it needs none)
    ++unjudged_cycles_;
    if (!braking_) return false;
    ++held_cycles_;
    Brake(sensors, c);
    return true;
  }
  int worst = -1;
  double predicted = INFINITY;
  if (clear) {
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
    budget_ = kBudget;
    last_evaluations_ = 0;
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
        clear = false;
        worst = i;
        predicted = b;
        if (budget_ <= 0) ++uncertified_cycles_;
        break;
      }
    }
    if (clear && unbrakeable >= 0) {
      ++warned_cycles_;
      if (unbrakeable_bound < warned_distance_)
        warned_distance_ = unbrakeable_bound, warned_pair_ = every_[unbrakeable];
    }
  }
  if (clear) {
    braking_ = false;
    std::fill(braked_.begin(), braked_.end(), 0);
    return false;
  }
  if (monitor_only_) {  // counted, the commands left alone
    ++warned_cycles_;
    if (worst >= 0 && predicted < warned_distance_) warned_distance_ = predicted, warned_pair_ = every_[worst];
    braking_ = false;
    return false;
  }
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
  return true;
}

}  // namespace ohrp::controllers
